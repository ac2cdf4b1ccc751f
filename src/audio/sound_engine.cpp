// SoundEngine: opens OpenAL Soft (default device, or the loopback device for offline WAVs), streams the two voices, keeps the file in time.
//
// Contents
//   1. OpenAL helpers: error names, the loopback extension's entry points, context binding
//   2. AlState: the device, the context, the two streams and their buffers
//   3. Opening: the live device (bounded by a timeout), the loopback device
//   4. Streaming: live top-up, offline mixing
//   5. SoundEngine
#include "audio/sound_engine.h"

#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <optional>
#include <thread>

#include "io/wav_file.h"

namespace dentsim::audio {

namespace {

// ---------------------------------------------------------------------------------------------
// 1. OpenAL helpers

// A mouth-sized scene heard from a camera a few centimetres to a few decimetres away: inside the
// reference distance the sources play at full gain (moving the bur about the tooth pans the sound
// but does not pump its loudness); farther out they fall off as 1/distance down to max distance.
constexpr double kReferenceDistanceM = 0.3;  // [m]
constexpr double kMaxDistanceM = 3.0;        // [m]
constexpr double kMetresPerMm = 1e-3;
// The longest gap between two offline inputs that the file follows; a longer jump starts a new
// segment instead, so that a corrupt time stamp cannot write hours of audio.
constexpr double kMaxOfflineGapS = 60.0;  // [s]
// Offline mixing granularity; also bounds the scratch buffers [frames].
constexpr int kOfflineChunkFrames = 1024;
constexpr int kStreams = 2;  // turbine, cutting

std::string hexCode(int code) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04X", unsigned(code));
  return text;
}

std::array<ALfloat, 3> metres(const Vec3& mm) {
  return {ALfloat(mm.x * kMetresPerMm), ALfloat(mm.y * kMetresPerMm), ALfloat(mm.z * kMetresPerMm)};
}

// ALC_SOFT_loopback's entry points, looked up at run time so that an OpenAL without the extension
// gives a readable error instead of a link failure.
struct LoopbackApi {
  LPALCLOOPBACKOPENDEVICESOFT open = nullptr;
  LPALCISRENDERFORMATSUPPORTEDSOFT supported = nullptr;
  LPALCRENDERSAMPLESSOFT render = nullptr;

  static std::optional<LoopbackApi> load() {
    if (alcIsExtensionPresent(nullptr, "ALC_SOFT_loopback") != ALC_TRUE) return std::nullopt;
    LoopbackApi api;
    api.open = reinterpret_cast<LPALCLOOPBACKOPENDEVICESOFT>(alcGetProcAddress(nullptr, "alcLoopbackOpenDeviceSOFT"));
    api.supported = reinterpret_cast<LPALCISRENDERFORMATSUPPORTEDSOFT>(
        alcGetProcAddress(nullptr, "alcIsRenderFormatSupportedSOFT"));
    api.render = reinterpret_cast<LPALCRENDERSAMPLESSOFT>(alcGetProcAddress(nullptr, "alcRenderSamplesSOFT"));
    if (!api.open || !api.supported || !api.render) return std::nullopt;
    return api;
  }
};

// The block [a, b] of the way from one input to the next, as an input: continuous quantities move
// linearly; contact switches half-way.
SoundInput lerpInput(const SoundInput& from, const SoundInput& to, double f) {
  if (f <= 0.0) return from;
  if (f >= 1.0) return to;
  auto mix = [f](double a, double b) { return a + (b - a) * f; };
  SoundInput s;
  s.t_s = mix(from.t_s, to.t_s);
  s.turbine_rpm = mix(from.turbine_rpm, to.turbine_rpm);
  s.removal_mm3_per_s = mix(from.removal_mm3_per_s, to.removal_mm3_per_s);
  for (size_t k = 0; k < s.removal_share.size(); ++k) {
    s.removal_share[k] = mix(from.removal_share[k], to.removal_share[k]);
  }
  s.force_n = mix(from.force_n, to.force_n);
  s.contact = f < 0.5 ? from.contact : to.contact;
  s.handpiece_mm = from.handpiece_mm + (to.handpiece_mm - from.handpiece_mm) * f;
  return s;
}

// What the device opened on a helper thread hands back; shared, so that an attempt that answers
// after create() gave up can still close what it opened.
struct OpenAttempt {
  std::mutex mutex;
  std::condition_variable answered;
  bool done = false;
  bool abandoned = false;
  ALCdevice* device = nullptr;
  ALCcontext* context = nullptr;
  std::string why;  // when device is null
};

// One source and the voice that feeds it, through a ring of AL buffers.
struct Stream {
  std::unique_ptr<Voice> voice;
  ALuint source = 0;
  std::vector<ALuint> buffers;      // all the buffers this stream owns
  std::vector<ALsizei> lengths;     // each buffer's data, by index in `buffers` [frames]
  std::vector<ALuint> free;         // those not queued
  ALsizei queued_frames = 0;        // in the queued buffers [frames]

  bool anyQueued() const { return free.size() < buffers.size(); }
  ALsizei& lengthOf(ALuint buffer) {
    const auto at = std::find(buffers.begin(), buffers.end(), buffer);
    assert(at != buffers.end());
    return lengths[size_t(at - buffers.begin())];
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// 2. AlState

// One engine's OpenAL objects and streaming state; the destructor deletes them in dependency order.
struct SoundEngine::AlState {
  ALCdevice* device = nullptr;
  ALCcontext* context = nullptr;
  std::optional<LoopbackApi> loopback;  // offline only
  bool float_source = true;              // AL_EXT_FLOAT32: voices go in as float, else as int16
  bool float_mix = true;                 // offline: the loopback mixes float32, else int16
  int sample_rate = 48000;               // [Hz]
  ALsizei chunk = 480;                   // frames per AL buffer
  ALsizei live_target = 0;               // live: how far each queue runs ahead [frames]
  std::array<Stream, kStreams> streams;

  // Scratch, sized once: no allocation while streaming.
  std::vector<float> mono;
  std::vector<int16_t> mono16;
  std::vector<float> stereo;
  std::vector<int16_t> stereo16;

  // Offline
  std::optional<WavWriter> writer;
  std::optional<Error> write_error;  // the first failed append, reported by finish()
  bool started = false;              // an input has been seen
  SoundInput previous;               // the last input
  uint64_t segment_frame = 0;        // where the current segment starts in the file [frames]
  int64_t segment_t_frames = 0;      // its first input's time [frames]

  AlState() = default;
  AlState(const AlState&) = delete;
  AlState& operator=(const AlState&) = delete;

  void bind() const {
    if (alcGetCurrentContext() != context) alcMakeContextCurrent(context);
  }

  // Sources let go of their buffers before either is deleted; the context goes before its device.
  ~AlState() {
    if (context) {
      bind();
      for (Stream& s : streams) {
        if (s.source) {
          alSourceStop(s.source);
          alSourcei(s.source, AL_BUFFER, 0);
          alDeleteSources(1, &s.source);
        }
        if (!s.buffers.empty()) alDeleteBuffers(ALsizei(s.buffers.size()), s.buffers.data());
      }
      alcMakeContextCurrent(nullptr);
      alcDestroyContext(context);
    }
    if (device) alcCloseDevice(device);
  }

  // Sources, buffers and the scene's distance law, once the context exists. Returns an AL error
  // code, or AL_NO_ERROR.
  ALenum setUpSources(int buffers_per_stream) {
    bind();
    alGetError();
    float_source = alIsExtensionPresent("AL_EXT_FLOAT32") == AL_TRUE;
    alDistanceModel(AL_INVERSE_DISTANCE_CLAMPED);
    alDopplerFactor(0.0f);  // no velocities are set; and a bur does not fly past the ear
    for (Stream& s : streams) {
      alGenSources(1, &s.source);
      s.buffers.assign(size_t(buffers_per_stream), 0);
      s.lengths.assign(size_t(buffers_per_stream), 0);
      alGenBuffers(buffers_per_stream, s.buffers.data());
      s.free = s.buffers;
      s.free.reserve(s.buffers.size());
      alSourcei(s.source, AL_SOURCE_RELATIVE, AL_FALSE);
      alSourcei(s.source, AL_LOOPING, AL_FALSE);
      alSourcef(s.source, AL_REFERENCE_DISTANCE, ALfloat(kReferenceDistanceM));
      alSourcef(s.source, AL_MAX_DISTANCE, ALfloat(kMaxDistanceM));
      alSourcef(s.source, AL_ROLLOFF_FACTOR, 1.0f);
      alSourcef(s.source, AL_GAIN, 1.0f);
      alSource3f(s.source, AL_POSITION, 0.0f, 0.0f, 0.0f);
    }
    mono.assign(size_t(chunk), 0.0f);
    mono16.assign(size_t(chunk), 0);
    return alGetError();
  }

  void placeSources(const Vec3& handpiece_mm) {
    const auto p = metres(handpiece_mm);
    for (Stream& s : streams) alSource3f(s.source, AL_POSITION, p[0], p[1], p[2]);
  }

  // Renders `frames` (<= chunk) of the stream's voice, `from` to `to`, into a free buffer and queues it.
  // False when every buffer is queued.
  bool queueBlock(Stream& s, const SoundInput& from, const SoundInput& to, ALsizei frames) {
    if (s.free.empty()) return false;
    const ALuint buffer = s.free.back();
    s.free.pop_back();
    const std::span<float> out(mono.data(), size_t(frames));
    s.voice->render(from, to, out);
    if (float_source) {
      alBufferData(buffer, AL_FORMAT_MONO_FLOAT32, mono.data(), frames * ALsizei(sizeof(float)), sample_rate);
    } else {
      for (size_t i = 0; i < out.size(); ++i) {
        mono16[i] = int16_t(std::lround(std::clamp(out[i], -1.0f, 1.0f) * 32767.0f));
      }
      alBufferData(buffer, AL_FORMAT_MONO16, mono16.data(), frames * ALsizei(sizeof(int16_t)), sample_rate);
    }
    alSourceQueueBuffers(s.source, 1, &buffer);
    s.lengthOf(buffer) = frames;
    s.queued_frames += frames;
    return true;
  }

  // Takes back the buffers the source has finished with.
  void reclaim(Stream& s) {
    ALint processed = 0;
    alGetSourcei(s.source, AL_BUFFERS_PROCESSED, &processed);
    while (processed-- > 0 && s.anyQueued()) {
      ALuint buffer = 0;
      alSourceUnqueueBuffers(s.source, 1, &buffer);
      if (buffer == 0) break;
      s.free.push_back(buffer);
      s.queued_frames -= s.lengthOf(buffer);
    }
  }

  // A source that ran dry stops (AL_STOPPED); one never started is AL_INITIAL. Either plays again
  // from its first queued buffer, which continues the voice where it left off.
  static void keepPlaying(const Stream& s) {
    ALint state = AL_INITIAL;
    alGetSourcei(s.source, AL_SOURCE_STATE, &state);
    if (state != AL_PLAYING && s.anyQueued()) alSourcePlay(s.source);
  }

  // ---------------------------------------------------------------------------------------------
  // 4. Streaming

  // Live: tops each queue up to live_target frames ahead of what the device has played, gliding
  // from `from` to `to` over what is added. Returns the frames added to the turbine's queue.
  uint64_t topUp(const SoundInput& from, const SoundInput& to) {
    uint64_t added_turbine = 0;
    placeSources(to.handpiece_mm);
    for (size_t k = 0; k < streams.size(); ++k) {
      Stream& s = streams[k];
      reclaim(s);
      ALint offset = 0;
      alGetSourcei(s.source, AL_SAMPLE_OFFSET, &offset);
      const ALsizei ahead = s.queued_frames - offset;
      const ALsizei missing = std::max<ALsizei>(live_target - ahead, 0);
      ALsizei done = 0;
      while (done < missing) {
        const ALsizei n = std::min(chunk, missing - done);
        const SoundInput a = lerpInput(from, to, double(done) / double(missing));
        const SoundInput b = lerpInput(from, to, double(done + n) / double(missing));
        if (!queueBlock(s, a, b, n)) break;
        done += n;
      }
      keepPlaying(s);
      if (k == 0) added_turbine = uint64_t(done);
    }
    return added_turbine;
  }

  // Offline: mixes `frames` frames gliding from `from` to `to` and appends them to the file.
  void mix(const SoundInput& from, const SoundInput& to, int64_t frames) {
    int64_t done = 0;
    while (done < frames) {
      const ALsizei n = ALsizei(std::min<int64_t>(chunk, frames - done));
      const SoundInput a = lerpInput(from, to, double(done) / double(frames));
      const SoundInput b = lerpInput(from, to, double(done + n) / double(frames));
      placeSources(b.handpiece_mm);
      // Exactly n frames go in and n come out, so each source plays its block to the end and
      // stops; the next block restarts it seamlessly.
      for (Stream& s : streams) {
        reclaim(s);
        const bool queued = queueBlock(s, a, b, n);
        assert(queued && "offline: every block is played before the next is queued");
        (void)queued;
        keepPlaying(s);
      }
      appendMix(n);
      done += n;
    }
  }

  void appendMix(ALsizei frames) {
    const size_t values = size_t(frames) * 2;
    if (float_mix) {
      loopback->render(device, stereo.data(), frames);
    } else {
      loopback->render(device, stereo16.data(), frames);
      for (size_t i = 0; i < values; ++i) stereo[i] = float(stereo16[i]) / 32768.0f;
    }
    if (write_error) return;
    Status appended = writer->append(std::span<const float>(stereo.data(), values));
    if (!appended.ok()) write_error = appended.error();
  }
};

namespace {

// ---------------------------------------------------------------------------------------------
// 3. Opening

// The default playback device and a context on it, opened on a helper thread: OpenAL Soft's
// backends (PulseAudio, JACK) can wait on a server that never answers, and the program must
// start anyway. On timeout the attempt is abandoned; whatever it opens later, it closes itself.
void openDefaultDevice(std::chrono::milliseconds timeout, ALCdevice*& device, ALCcontext*& context, std::string& why) {
  auto attempt = std::make_shared<OpenAttempt>();
  std::thread([attempt] {
    std::string reason;
    ALCdevice* d = alcOpenDevice(nullptr);
    ALCcontext* c = nullptr;
    if (!d) {
      reason = "OpenAL could not open the default output, ALC error " + hexCode(alcGetError(nullptr));
    } else {
      c = alcCreateContext(d, nullptr);
      if (!c) {
        reason = "OpenAL could not start the default output, ALC error " + hexCode(alcGetError(d));
        alcCloseDevice(d);
        d = nullptr;
      }
    }
    std::lock_guard lock(attempt->mutex);
    if (attempt->abandoned) {
      if (c) alcDestroyContext(c);
      if (d) alcCloseDevice(d);
      return;
    }
    attempt->device = d;
    attempt->context = c;
    attempt->why = reason;
    attempt->done = true;
    attempt->answered.notify_one();
  }).detach();

  std::unique_lock lock(attempt->mutex);
  if (!attempt->answered.wait_for(lock, timeout, [&] { return attempt->done; })) {
    attempt->abandoned = true;
    why = "opening the default output did not answer in " + std::to_string(timeout.count()) + " ms";
    return;
  }
  device = attempt->device;
  context = attempt->context;
  why = attempt->why;
}

Result<std::unique_ptr<Voice>> makeVoice(const EngineOptions& o, const SynthParams& synth, SampleRole role) {
  const std::string& wav = role == SampleRole::Turbine ? o.turbine_wav : o.cutting_wav;
  const char* what = role == SampleRole::Turbine ? "turbine sample" : "cutting sample";
  if (!wav.empty()) {
    auto voice = makeSampleVoice(wav, role, o.recorded_rpm, synth);
    if (!voice) return makeError(what, voice.message());
    return std::move(voice).value();
  }
  return role == SampleRole::Turbine ? makeTurbineVoice(synth) : makeCuttingVoice(synth);
}

Status checkOptions(const EngineOptions& o) {
  const std::string where = o.audio_out.empty() ? "sound" : "sound (" + o.audio_out + ")";
  if (o.sample_rate < 8000 || o.sample_rate > 192000) {
    return makeError(where, "sample rate " + std::to_string(o.sample_rate) + " Hz is outside 8000..192000");
  }
  if (!(o.latency_s >= 0.01 && o.latency_s <= 1.0)) {
    return makeError(where, "latency " + std::to_string(o.latency_s) + " s is outside 0.01..1");
  }
  if (!o.turbine_wav.empty() && !(o.recorded_rpm > 0 && std::isfinite(o.recorded_rpm))) {
    return makeError(where, "recorded rpm of the turbine sample must be positive");
  }
  return Ok{};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 5. SoundEngine

Result<std::unique_ptr<SoundEngine>> SoundEngine::create(const EngineOptions& options) {
  if (Status ok = checkOptions(options); !ok) return ok.error();
  SynthParams synth = options.synth;
  synth.sample_rate = double(options.sample_rate);

  // Voices first, in every mode: a bad sample file is the user's mistake even without a device.
  auto turbine = makeVoice(options, synth, SampleRole::Turbine);
  if (!turbine) return turbine.error();
  auto cutting = makeVoice(options, synth, SampleRole::Cutting);
  if (!cutting) return cutting.error();

  std::unique_ptr<SoundEngine> engine(new SoundEngine());
  auto st = std::make_unique<AlState>();
  st->sample_rate = options.sample_rate;
  st->streams[0].voice = std::move(turbine).value();
  st->streams[1].voice = std::move(cutting).value();

  if (!options.audio_out.empty()) {
    // Offline: the loopback device mixes only when asked, at our rate, into our buffer.
    const std::string where = "--audio-out " + options.audio_out;
    st->loopback = LoopbackApi::load();
    if (!st->loopback) return makeError(where, "this OpenAL has no ALC_SOFT_loopback, cannot render offline");
    st->device = st->loopback->open(nullptr);
    if (!st->device) return makeError(where, "OpenAL could not open a loopback device");
    const ALCsizei rate = options.sample_rate;
    if (st->loopback->supported(st->device, rate, ALC_STEREO_SOFT, ALC_FLOAT_SOFT) == ALC_TRUE) {
      st->float_mix = true;
    } else if (st->loopback->supported(st->device, rate, ALC_STEREO_SOFT, ALC_SHORT_SOFT) == ALC_TRUE) {
      st->float_mix = false;
    } else {
      return makeError(where, "the loopback device renders neither float32 nor int16 stereo at " +
                                  std::to_string(rate) + " Hz");
    }
    // Plain stereo panning, no HRTF, and no limiter: the file must be a linear mix (volume 0.5 is
    // half the amplitude); the WAV writer clamps what exceeds full scale.
    const ALCint attributes[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT,
                                 ALC_FORMAT_TYPE_SOFT,     st->float_mix ? ALC_FLOAT_SOFT : ALC_SHORT_SOFT,
                                 ALC_FREQUENCY,            rate,
                                 ALC_HRTF_SOFT,            ALC_FALSE,
                                 ALC_OUTPUT_LIMITER_SOFT,  ALC_FALSE,
                                 0};
    st->context = alcCreateContext(st->device, attributes);
    if (!st->context) {
      return makeError(where, "OpenAL could not create the loopback context, ALC error " +
                                  hexCode(alcGetError(st->device)));
    }
    st->chunk = kOfflineChunkFrames;
    // One block is queued and played per source at a time; two spare buffers keep reclaim simple.
    if (ALenum e = st->setUpSources(3); e != AL_NO_ERROR) {
      return makeError(where, "OpenAL could not set up the sources, AL error " + hexCode(e));
    }
    st->stereo.assign(size_t(st->chunk) * 2, 0.0f);
    st->stereo16.assign(size_t(st->chunk) * 2, 0);
    auto writer = WavWriter::create(options.audio_out, 2, options.sample_rate);
    if (!writer) return writer.error();
    st->writer.emplace(std::move(writer).value());
    engine->offline_ = true;
    engine->state_ = std::move(st);
    engine->setListener(Vec3{0, 0, 200}, Vec3{0, 0, -1}, Vec3{0, 1, 0});
    return engine;
  }

  // Live: any failure from here on gives a silent engine, never an error.
  if (options.force_silent) {
    engine->notice_ = "no sound device (sound switched off): running silently";
    return engine;
  }
  std::string why;
  openDefaultDevice(kOpenTimeout, st->device, st->context, why);
  if (!st->context) {
    engine->notice_ = "no sound device (" + why + "): running silently";
    return engine;
  }
  st->chunk = ALsizei(std::max(64, options.sample_rate / 100));  // 10 ms buffers
  st->live_target = ALsizei(std::ceil(options.latency_s * options.sample_rate));
  const int buffers = int((st->live_target + st->chunk - 1) / st->chunk) + 2;
  if (ALenum e = st->setUpSources(buffers); e != AL_NO_ERROR) {
    engine->notice_ = "no sound device (OpenAL could not set up the sources, AL error " + hexCode(e) +
                      "): running silently";
    return engine;  // st's destructor closes the device
  }
  engine->state_ = std::move(st);
  engine->setListener(Vec3{0, 0, 200}, Vec3{0, 0, -1}, Vec3{0, 1, 0});
  return engine;
}

bool SoundEngine::offlineAvailable() { return LoopbackApi::load().has_value(); }

SoundEngine::~SoundEngine() = default;

void SoundEngine::setListener(const Vec3& position_mm, const Vec3& forward, const Vec3& up) {
  if (!state_ || !finite(position_mm) || !finite(forward) || !finite(up)) return;
  const Vec3 f = normalized(forward);
  const Vec3 u = normalized(up);
  if (norm(f) == 0.0 || norm(u) == 0.0) return;
  state_->bind();
  const auto p = metres(position_mm);
  alListener3f(AL_POSITION, p[0], p[1], p[2]);
  const ALfloat orientation[6] = {ALfloat(f.x), ALfloat(f.y), ALfloat(f.z), ALfloat(u.x), ALfloat(u.y), ALfloat(u.z)};
  alListenerfv(AL_ORIENTATION, orientation);
}

void SoundEngine::update(const SoundInput& in) {
  if (!state_ || finished_ || !std::isfinite(in.t_s)) return;
  AlState& st = *state_;
  st.bind();
  if (!offline_) {
    // The device keeps its own clock; time only orders the inputs.
    const SoundInput& from = st.started ? st.previous : in;
    frames_ += st.topUp(from, in);
    st.previous = in;
    st.started = true;
    return;
  }
  const int64_t t_frames = std::llround(in.t_s * double(st.sample_rate));
  const bool fresh = !st.started || in.t_s < st.previous.t_s || in.t_s - st.previous.t_s > kMaxOfflineGapS;
  if (fresh) {
    // A new segment starts where the file stands; the voices keep their phase and rotor speed,
    // so nothing clicks.
    st.segment_frame = frames_;
    st.segment_t_frames = t_frames;
    st.previous = in;
    st.started = true;
    return;
  }
  const int64_t target = int64_t(st.segment_frame) + (t_frames - st.segment_t_frames);
  const int64_t frames = target - int64_t(frames_);
  if (frames > 0) {
    st.mix(st.previous, in, frames);
    frames_ += uint64_t(frames);
  }
  st.previous = in;
}

void SoundEngine::setVolume(double volume) {
  if (!std::isfinite(volume)) return;
  volume_ = std::clamp(volume, 0.0, 1.0);
  if (!state_) return;
  state_->bind();
  alListenerf(AL_GAIN, mute_ ? 0.0f : ALfloat(volume_));
}

void SoundEngine::setMute(bool mute) {
  mute_ = mute;
  if (!state_) return;
  state_->bind();
  alListenerf(AL_GAIN, mute_ ? 0.0f : ALfloat(volume_));
}

Status SoundEngine::finish() {
  if (finished_ || !state_ || !offline_) {
    finished_ = true;
    return Ok{};
  }
  finished_ = true;
  if (state_->write_error) return *state_->write_error;
  return state_->writer->finish();
}

}  // namespace dentsim::audio
