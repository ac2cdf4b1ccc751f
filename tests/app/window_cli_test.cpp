// The simulator window end to end: under Xvfb on lavapipe, `dentsim run` plays the demo path and its screenshots show the tooth, the bur, the mirror's reflection and the parameter window; the cut changes the tooth; headless frames equal windowed ones; two pens at once, one a hardware backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/png_file.h"
#include "io/session_file.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readJson;
using test::runDentsim;
using test::TempDir;

using test::haveXvfb;

// Tissue as the default looks shade it: lit enamel and dentin are light and warm (red above blue),
// caries brown (warm, darker). The background, the steel and the ImGui panel are neutral or cool.
bool toothColoured(const std::array<uint8_t, 3>& p) {
  const int r = p[0], g = p[1], b = p[2];
  return r >= 60 && r >= b + 18 && g >= b;
}
// The bur and the handpiece: grey steel, neither warm nor dark.
bool steelColoured(const std::array<uint8_t, 3>& p) {
  const int r = p[0], g = p[1], b = p[2];
  const int hi = std::max({r, g, b}), lo = std::min({r, g, b});
  return hi >= 45 && hi - lo <= 20;
}

// Pixels of `image` within `radius` of (cx, cy) that pass `test`, and how many were looked at.
template <class Test>
std::pair<int, int> countNear(const RgbImage& image, double cx, double cy, double radius, Test test) {
  int hits = 0, seen = 0;
  for (int y = int(cy - radius); y <= int(cy + radius); ++y)
    for (int x = int(cx - radius); x <= int(cx + radius); ++x) {
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      if (std::hypot(x - cx, y - cy) > radius) continue;
      ++seen;
      if (test(image.pixel(x, y))) ++hits;
    }
  return {hits, seen};
}

// A fast preset: the demo path at level 7 takes about a second of loop time.
std::string writeFastPreset(const TempDir& dir) {
  const std::string preset = dir.file("fast.json");
  std::ofstream(preset) << R"({"format":"dentsim-params","version":1,"cutting":{"removal_rate_mm3_per_s":40},)"
                           R"("point_shell":{"head_spacing_mm":0.1,"shank_spacing_mm":0.2}})";
  return preset;
}

class WindowCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  }
  // `dentsim ARGS` inside a fresh virtual display of 1280x800.
  test::CommandResult runInXvfb(const std::string& args) {
    const test::NoLeakCheckForGpuChild no_leak_check;
    return test::runCommand("DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) + " " + args);
  }
};

TEST_F(WindowCli, ScreenshotsShowToothBurMirrorReflectionAndPanelAndTheCut) {
  TempDir dir;
  const std::string out = dir.file("shots");
  const auto r = runInXvfb("run --level 7 --params " + writeFastPreset(dir) +
                           " --demo-script --lockstep --fps 4 --exit-at-end --width 1280 --height 720 --shot 0.05 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json first = readJson(out + "/shot-1.json"), last = readJson(out + "/shot-final.json");
  ASSERT_FALSE(first.is_discarded()) << r.output;
  ASSERT_FALSE(last.is_discarded()) << r.output;
  EXPECT_TRUE(first["windowed"].get<bool>()) << "the run fell back to headless: " << r.output;
  auto a = readPng(out + "/shot-1.png"), b = readPng(out + "/shot-final.png");
  ASSERT_TRUE(a) << a.message();
  ASSERT_TRUE(b) << b.message();
  ASSERT_EQ(a->width, 1280);
  ASSERT_EQ(a->height, 720);

  // The tooth: tissue colours fill most of a disc around the crown's projected centre.
  const double tcx = first["tooth_centre_px"][0], tcy = first["tooth_centre_px"][1];
  auto [tooth_hits, tooth_seen] = countNear(*a, tcx, tcy, 40, toothColoured);
  EXPECT_GT(tooth_hits, tooth_seen / 2) << "tooth pixels near (" << tcx << ", " << tcy << ")";

  // The bur: steel on its shank, 4 mm above the tip.
  const double bx = first["bur_shank_px"][0], by = first["bur_shank_px"][1];
  auto [steel_hits, steel_seen] = countNear(*a, bx, by, 4, steelColoured);
  EXPECT_GT(steel_hits, steel_seen / 2) << "bur pixels near (" << bx << ", " << by << ")";

  // The mirror faces the eye, and its face shows the tooth: warm tissue colours inside the glass,
  // which holds nothing warm of its own.
  ASSERT_TRUE(first.contains("mirror_centre_px"));
  EXPECT_TRUE(first["mirror_faces_eye"].get<bool>());
  const double mx = first["mirror_centre_px"][0], my = first["mirror_centre_px"][1];
  const double mr = first["mirror_radius_px"];
  auto [reflected, glass] = countNear(*a, mx, my, 0.6 * mr, toothColoured);
  EXPECT_GT(reflected, glass / 20) << "reflected tooth pixels in the mirror at (" << mx << ", " << my << "), r " << mr;

  // The parameter window: its rectangle holds ImGui's dark window background and light text.
  ASSERT_TRUE(first.contains("panel_rect"));
  const int px = first["panel_rect"][0], py = first["panel_rect"][1], pw = first["panel_rect"][2], ph = first["panel_rect"][3];
  ASSERT_GT(pw, 100);
  ASSERT_GT(ph, 100);
  int dark = 0, text = 0, seen = 0;
  for (int y = py; y < std::min(py + ph, a->height); ++y)
    for (int x = px; x < std::min(px + pw, a->width); ++x) {
      const auto p = a->pixel(x, y);
      ++seen;
      if (p[0] < 40 && p[1] < 40 && p[2] < 40) ++dark;
      if (p[0] > 200 && p[1] > 200 && p[2] > 200) ++text;
    }
  EXPECT_GT(dark, seen / 3);
  EXPECT_GT(text, seen / 200);

  // The cut: tooth pixels whose shade changed between the two shots, where the tooth shows in
  // both (so that the bur moving over it does not count).
  ASSERT_GT(last["removed_mm3"].get<double>(), 0.5) << r.output;
  int changed = 0;
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) {
      const auto p = a->pixel(x, y), q = b->pixel(x, y);
      if (!toothColoured(p) || !toothColoured(q)) continue;
      if (std::abs(int(p[0]) - int(q[0])) + std::abs(int(p[1]) - int(q[1])) + std::abs(int(p[2]) - int(q[2])) > 45) ++changed;
    }
  EXPECT_GT(changed, 300) << "tooth pixels changed by the cut";

  // The pictures for docs/ and the README come from this run when asked.
  if (const char* keep = std::getenv("DENTSIM_KEEP_SCREENSHOTS")) {
    std::filesystem::create_directories(keep);
    for (const char* f : {"shot-1.png", "shot-final.png"})
      std::filesystem::copy_file(out + "/" + f, std::string(keep) + "/" + f, std::filesystem::copy_options::overwrite_existing);
  }
}

TEST_F(WindowCli, HeadlessFramesEqualWindowedFramesOfTheSameState) {
  TempDir dir;
  const std::string preset = writeFastPreset(dir);
  const std::string common = "run --level 7 --params " + preset + " --demo-script --lockstep --no-ui --width 640 --height 400 "
                             "--shot 0.3 --exit-after 0.35 --out ";
  const auto w = runInXvfb(common + dir.file("window"));
  ASSERT_EQ(w.exit_code, 0) << w.output;
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto h = test::runCommand("DENTSIM_VALIDATION=1 " + std::string(DENTSIM_BINARY) + " " + common + dir.file("headless") + " --headless");
  ASSERT_EQ(h.exit_code, 0) << h.output;
  EXPECT_TRUE(readJson(dir.file("window/shot-1.json"))["windowed"].get<bool>()) << w.output;
  EXPECT_FALSE(readJson(dir.file("headless/shot-1.json"))["windowed"].get<bool>()) << h.output;
  auto a = readPng(dir.file("window/shot-1.png")), b = readPng(dir.file("headless/shot-1.png"));
  ASSERT_TRUE(a) << a.message();
  ASSERT_TRUE(b) << b.message();
  ASSERT_EQ(a->width, b->width);
  ASSERT_EQ(a->height, b->height);
  // Both are 8-bit UNORM of the same draws: equal up to the colour format's rounding, one step.
  int worst = 0;
  for (size_t i = 0; i < a->rgb.size(); ++i) worst = std::max(worst, std::abs(int(a->rgb[i]) - int(b->rgb[i])));
  EXPECT_LE(worst, 1);
  // And the frame is not empty: the tooth is in it.
  int tooth = 0;
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) tooth += toothColoured(a->pixel(x, y));
  EXPECT_GT(tooth, a->width * a->height / 50);
}

// Device names that name nothing usable fail at once, in one line naming the pen and the device,
// with no window needed.
TEST(DeviceCli, MissingOrUnknownPensAreOneLineErrors) {
  const auto falcon = runDentsim("run --level 6 --drill falcon:0 --exit-after 0.1 --headless");
  EXPECT_EQ(falcon.exit_code, 1) << falcon.output;
  EXPECT_NE(falcon.output.find("drill pen: falcon:0:"), std::string::npos) << falcon.output;
  const auto unknown = runDentsim("run --level 6 --mirror joystick --exit-after 0.1 --headless");
  EXPECT_EQ(unknown.exit_code, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("mirror pen: pen 'joystick'"), std::string::npos) << unknown.output;
  const auto absent = test::runCommand("DENTSIM_OPENHAPTICS_LIB=/nonexistent/libHD.so " + std::string(DENTSIM_BINARY) +
                                       " run --level 6 --drill openhaptics --exit-after 0.1 --headless");
  EXPECT_EQ(absent.exit_code, 1) << absent.output;
  EXPECT_NE(absent.output.find("OpenHaptics not installed"), std::string::npos) << absent.output;
  const auto pedal = runDentsim("run --level 6 --pedal usb --exit-after 0.1 --headless");
  EXPECT_EQ(pedal.exit_code, 1) << pedal.output;
  EXPECT_NE(pedal.output.find("pedal 'usb'"), std::string::npos) << pedal.output;
}

#ifdef DENTSIM_FAKE_HD_LIB
// Two pens at once: the drill on an OpenHaptics pen (the fake HDAPI library, loaded by the plug-in
// as it would load libHD.so) and the mirror on the virtual pen, in a window with the real-time
// loop. `dentsim devices` lists the pen as ready; the session records both pens at every step, the
// drill where the still pen holds it.
TEST_F(WindowCli, TwoPensAtOnceAHardwareDrillAndAVirtualMirror) {
  TempDir dir;
  const std::string env = std::string("DENTSIM_OPENHAPTICS_LIB=") + DENTSIM_FAKE_HD_LIB + " ";
  const auto list = test::runCommand(env + DENTSIM_BINARY + " devices --json");
  ASSERT_EQ(list.exit_code, 0) << list.output;
  const nlohmann::json devices = nlohmann::json::parse(list.output, nullptr, false);
  ASSERT_TRUE(devices.is_array()) << list.output;
  bool listed = false;
  for (const auto& d : devices)
    if (d["name"] == "openhaptics:Default") listed = d["state"] == "ready" && d["usable"] == true;
  EXPECT_TRUE(listed) << list.output;

  const std::string out = dir.file("pens");
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runCommand(env + "DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " +
                                  std::string(DENTSIM_BINARY) + " run --level 6 --params " + writeFastPreset(dir) +
                                  " --drill openhaptics:Default --mirror virtual --exit-after 0.5 --no-ui"
                                  " --width 640 --height 400 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto session = readSessionFile(out + "/session.dses");
  ASSERT_TRUE(session.ok()) << session.message() << "\n" << r.output;
  ASSERT_GE(session->steps.size(), 400u) << "0.5 s of loop time at 1 kHz";
  const Pose drill = session->steps.front().reading[0].grip;
  for (const SessionStep& s : session->steps) {
    ASSERT_TRUE(s.hasReading(0) && s.hasReading(1)) << "step " << s.step;
    EXPECT_EQ(s.reading[0].grip, drill) << "step " << s.step << ": the fake pen holds still";
    EXPECT_EQ(s.reading[0].pedal, 0.0);
  }
}

// The paper's pair: the drill and the mirror each on an OpenHaptics pen ("Left" and "Right", as
// Touch Setup names them), both served by the fake HDAPI's one scheduler. Once the session is
// being recorded, the mirror's device fails (SIGUSR1 to dentsim, which the fake turns into an HD
// error on the mirror's next frame); once dentsim has said so, Ctrl-C ends the run. The run says
// which pen failed and that both forces are zero, records the failure in the session, and
// replays exactly; the fake saw no force after its scheduler stopped and no pen left pushing.
// Every wait is for an event, bounded (60 s each), never a guess at how long something takes.
TEST_F(WindowCli, TwoOpenHapticsPensAndAFaultOnTheMirrorPen) {
  TempDir dir;
  std::filesystem::create_directories(dir.path() / "gtdd" / "config");
  for (const char* name : {"Left", "Right"})
    std::ofstream(dir.path() / "gtdd" / "config" / (std::string(name) + ".config")) << "[fake]\n";
  const std::string log = dir.file("fake_hd.log");
  const std::string env = std::string("DENTSIM_OPENHAPTICS_LIB=") + DENTSIM_FAKE_HD_LIB + " GTDD_HOME=" +
                          (dir.path() / "gtdd").string() + " DENTSIM_FAKE_HD_LOG=" + log + " ";
  const auto list = test::runCommand(env + DENTSIM_BINARY + " devices --json");
  ASSERT_EQ(list.exit_code, 0) << list.output;
  const nlohmann::json devices = nlohmann::json::parse(list.output, nullptr, false);
  ASSERT_TRUE(devices.is_array()) << list.output;
  int ready = 0;
  for (const auto& d : devices)
    if (d["name"] == "openhaptics:Left" || d["name"] == "openhaptics:Right") ready += d["state"] == "ready" ? 1 : 0;
  EXPECT_EQ(ready, 2) << list.output;
  std::filesystem::remove(log);  // the listing's own probe

  const std::string out = dir.file("pens");
  const std::string said = dir.file("run.txt");
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runCommand(
      env + "DENTSIM_FAKE_HD_FAULT=Right@signal DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' sh -c '" +
      std::string(DENTSIM_BINARY) + " run --level 6 --params " + writeFastPreset(dir) +
      " --drill openhaptics:Left --mirror openhaptics:Right --exit-after 120 --no-ui --width 640 --height 400 --out " +
      out + " >" + said + " 2>&1 & pid=$!; part=" + out + "/session.dses.part; " +
      R"(n=0; while [ $n -lt 1200 ] && ! { [ -f $part ] && [ $(stat -c %s $part) -gt 100000 ]; }; do sleep 0.05; n=$((n+1)); done; )"
      R"(kill -USR1 $pid; )"
      "n=0; while [ $n -lt 1200 ] && ! grep -q \"openhaptics:Right: fault\" " + said + "; do sleep 0.05; n=$((n+1)); done; " +
      "kill -INT $pid; wait $pid; s=$?; cat " + said + "; exit $s'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("mirror pen openhaptics:Right: fault"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("communication error"), std::string::npos) << r.output;
  // Which pen the line names is the first to fail: the mirror, unless a loaded machine stalled the
  // loop past the drill's 3 ms watchdog first, which is as much a fault and zeroes both the same way.
  EXPECT_NE(r.output.find(" pen failed: both pens' forces are zero"), std::string::npos) << r.output;
  auto session = readSessionFile(out + "/session.dses");
  ASSERT_TRUE(session.ok()) << session.message() << "\n" << r.output;
  ASSERT_GE(session->steps.size(), 300u);
  for (const SessionStep& s : session->steps) ASSERT_TRUE(s.hasReading(0) && s.hasReading(1)) << "step " << s.step;
  const auto mirror_fault = std::find_if(session->devices.begin(), session->devices.end(), [](const auto& e) {
    return e.pen == 1 && e.state == "fault" && e.reason.find("communication error") != std::string::npos;
  });
  ASSERT_NE(mirror_fault, session->devices.end()) << r.output;
  const auto replay = runDentsim("replay " + out + "/session.dses --headless --json");
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  const nlohmann::json replayed = test::printedJson(replay.output);
  EXPECT_EQ(replayed.value("matches_recording", false), true) << replay.output;
  EXPECT_EQ(replayed.value("force_mismatches", -1), 0) << replay.output;
  ASSERT_TRUE(replayed.contains("device_events")) << replay.output;
  bool replay_names_it = false;
  for (const auto& e : replayed["device_events"]) replay_names_it |= e["pen"] == "mirror" && e["state"] == "fault";
  EXPECT_TRUE(replay_names_it) << replay.output;

  // The fake's account of the run: one line per pen at each scheduler stop and at unloading.
  std::ifstream in(log);
  std::string line;
  int unload_lines = 0;
  while (std::getline(in, line)) {
    EXPECT_NE(line.find("sent_after_stop=0 "), std::string::npos) << line;
    EXPECT_NE(line.find("stopped_pushing=0 "), std::string::npos) << line;
    EXPECT_NE(line.find("misuse=0"), std::string::npos) << line;
    if (line.rfind("unload Right ", 0) == 0) {
      ++unload_lines;
      EXPECT_EQ(line.find("error_tick=-1"), std::string::npos) << "the fault was never raised: " << line;
    }
    if (line.rfind("unload Left ", 0) == 0) ++unload_lines;
  }
  EXPECT_EQ(unload_lines, 2);
}
#endif

}  // namespace
}  // namespace dentsim
