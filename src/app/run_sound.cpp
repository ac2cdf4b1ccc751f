// The simulator's sound engine and what feeds it each frame.
#include "app/run_sound.h"

#include <filesystem>

#include "sim/tool_library.h"

namespace dentsim::app {

Result<std::string> RunSound::open(const RunSoundOptions& o, bool headless, const std::function<void(const std::string&)>& note) {
  if (!o.sound || (headless && o.audio_out.empty())) return std::string("no sound");
  audio::EngineOptions eo;
  eo.audio_out = o.audio_out;
  eo.turbine_wav = o.turbine_wav;
  eo.cutting_wav = o.cutting_wav;
  eo.recorded_rpm = o.recorded_rpm;
  auto engine = audio::SoundEngine::create(eo);
  if (!engine) return makeError("sound", engine.message());
  engine_ = std::move(*engine);
  if (engine_->silent()) {
    note("dentsim: " + engine_->notice());
    return engine_->notice();
  }
  return engine_->offline() ? "writing " + std::filesystem::path(o.audio_out).filename().string() : std::string("OpenAL Soft");
}

void RunSound::update(const render::OrbitCamera& camera, double volume, bool mute, const HapticState& state) {
  if (!engine_) return;
  const render::CameraBasis basis = camera.basis();
  engine_->setListener(render::fromGlm(camera.eye()), render::fromGlm(basis.forward), render::fromGlm(basis.up));
  engine_->setVolume(volume);
  engine_->setMute(mute);
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  engine_->update(feed_.next(state, drill.tool.apply(kBurGripLocal)));
}

}  // namespace dentsim::app
