// The golden session: the level-7 demo recorded on 2026-11-26 replays to the same final volume and score, and its windowed screenshot still looks the same.
//
// The fixture (tests/golden/level7_demo, README.md there) was made by the build of that day, before
// the architecture step of issue 23. It guards every later change: a change that moves one voxel of
// the recorded session's final tooth, one bit of its score, or more than a few pixels of the picture
// fails here, and must say why in its commit (and re-record the fixture as the README says).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <zstd.h>

#include "io/dvol_file.h"
#include "io/png_file.h"
#include "test_json.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
using test::readJson;
using test::runDentsim;
using test::TempDir;

const std::filesystem::path kFixture = std::filesystem::path(DENTSIM_SOURCE_DIR) / "tests/golden/level7_demo";

// The session is kept zstd-compressed (24.7 MB raw, 3.5 MB packed); the test unpacks it into `out`.
::testing::AssertionResult unpackSession(const std::string& out) {
  const std::vector<uint8_t> packed = readBytes(kFixture / "session.dses.zst");
  if (packed.empty()) return ::testing::AssertionFailure() << kFixture / "session.dses.zst" << " is missing or empty";
  const unsigned long long size = ZSTD_getFrameContentSize(packed.data(), packed.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > (1ull << 30))
    return ::testing::AssertionFailure() << "session.dses.zst: no usable content size";
  std::vector<uint8_t> raw(size);
  const size_t got = ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
  if (ZSTD_isError(got) || got != size)
    return ::testing::AssertionFailure() << "session.dses.zst: " << (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "short");
  test::writeBytes(out, raw);
  return ::testing::AssertionSuccess();
}

// The score report without the paths of this run's files, which name a temporary folder.
nlohmann::json withoutPaths(nlohmann::json report) {
  if (report.contains("inputs"))
    for (const char* key : {"initial", "final", "session"}) report["inputs"].erase(key);
  return report;
}

// One replay for the suite: the session is long (77 s of loop time, both pens), so it runs once.
class GoldenSession : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    unpacked_ = unpackSession(dir_->file("session.dses"));
    if (unpacked_)
      replay_ = new test::CommandResult(runDentsim("replay " + dir_->file("session.dses") + " --headless --out " + dir_->file("replayed") +
                                                   " --report " + dir_->file("score.json")));
  }
  static void TearDownTestSuite() {
    delete replay_;
    delete dir_;
  }
  void SetUp() override {
    ASSERT_TRUE(unpacked_);
    ASSERT_EQ(replay_->exit_code, 0) << replay_->output;
  }

  static TempDir* dir_;
  static ::testing::AssertionResult unpacked_;
  static test::CommandResult* replay_;
};
TempDir* GoldenSession::dir_ = nullptr;
::testing::AssertionResult GoldenSession::unpacked_ = ::testing::AssertionFailure();
test::CommandResult* GoldenSession::replay_ = nullptr;

TEST_F(GoldenSession, ReplaysToTheRecordedFinalVolumeWordForWord) {
  // The replay itself checks the recording's final hash. The fixture was written as a version 1
  // .dvol, before the tooth frame (issue 24) joined the header: the grid and every word of the
  // payload must still be the same, and the replay's file carries the molar's given frame.
  EXPECT_NE(replay_->output.find("(the recording's)"), std::string::npos) << replay_->output;
  auto expected = readVolumeFile((kFixture / "final.dvol").string());
  auto got = readVolumeFile(dir_->file("replayed") + "/final.dvol");
  ASSERT_TRUE(expected.ok()) << expected.message();
  ASSERT_TRUE(got.ok()) << got.message();
  EXPECT_EQ(got->frame.level, expected->frame.level);
  EXPECT_EQ(got->frame.voxel_mm, expected->frame.voxel_mm);
  EXPECT_EQ(got->frame.origin_mm, expected->frame.origin_mm);
  EXPECT_EQ(got->frame.scanner_from_grid, expected->frame.scanner_from_grid);
  EXPECT_EQ(got->frame.source_offset, expected->frame.source_offset);
  EXPECT_EQ(got->frame.source_dims, expected->frame.source_dims);
  EXPECT_TRUE(got->chunks == expected->chunks) << "chunk words differ from tests/golden/level7_demo/final.dvol";
  EXPECT_TRUE(got->blocks == expected->blocks) << "index block words differ from tests/golden/level7_demo/final.dvol";
  EXPECT_TRUE(got->bricks == expected->bricks) << "brick words differ from tests/golden/level7_demo/final.dvol";
  EXPECT_EQ(got->frame.tooth.crown_source, AxisSource::Given);
  EXPECT_EQ(got->frame.tooth.crown, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(got->frame.tooth.mesial, (std::array<double, 3>{-1, 0, 0}));
  EXPECT_FALSE(got->frame.tooth.turned());
}

TEST_F(GoldenSession, ScoresTheSameToTheLastBit) {
  const nlohmann::json expected = readJson(kFixture / "score.json");
  const nlohmann::json got = readJson(dir_->file("score.json"));
  ASSERT_FALSE(expected.is_discarded());
  ASSERT_FALSE(got.is_discarded());
  // JSON keeps doubles to the last bit (shortest round trip), so equal text means equal numbers.
  EXPECT_EQ(withoutPaths(got).dump(1), withoutPaths(expected).dump(1));
  EXPECT_DOUBLE_EQ(got["total"].get<double>(), expected["total"].get<double>());
}

using test::haveXvfb;

// The windowed screenshot of the same demo at 6 s of loop time, in lockstep so that it shows exactly
// that state, against the one taken on the fixture's day. The statistics overlay in the top-left
// corner (frame and re-mesh times, the haptic rate) is measured in wall time and differs on every
// run, so it is left out; everything else (tooth, tools, the mirror's view, the cut, the parameter
// window) must match to within a few pixels.
TEST(GoldenScreenshot, TheWindowedShotAtSixSecondsDiffersByAtMostAFewPixels) {
  if (!haveXvfb()) GTEST_SKIP() << "no X server for tests: xvfb-run and Xvfb are not installed (Debian: xvfb xauth)";
  TempDir dir;
  const test::NoLeakCheckForGpuChild no_leak_check;
  const auto r = test::runCommand("DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) +
                                  " run --level 7 --demo-script --lockstep --no-sound --shot 6 --exit-after 6.05 --out " +
                                  dir.file("w"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(readJson(dir.file("w/shot-1.json"))["windowed"].get<bool>()) << "the run fell back to headless: " << r.output;
  auto got = readPng(dir.file("w/shot-1.png"));
  auto expected = readPng((kFixture / "shot-6s.png").string());
  ASSERT_TRUE(got) << got.message();
  ASSERT_TRUE(expected) << expected.message();
  ASSERT_EQ(got->width, expected->width);
  ASSERT_EQ(got->height, expected->height);

  constexpr int kOverlayRight = 260, kOverlayBottom = 160;  // the statistics overlay at 1280 x 800
  constexpr int kTolerance = 2;                             // colour steps: rounding, not a change
  int differing = 0, worst = 0;
  for (int y = 0; y < got->height; ++y)
    for (int x = 0; x < got->width; ++x) {
      if (x < kOverlayRight && y < kOverlayBottom) continue;
      const auto a = got->pixel(x, y), b = expected->pixel(x, y);
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a[c]) - int(b[c])));
      worst = std::max(worst, d);
      differing += d > kTolerance;
    }
  EXPECT_LE(differing, 16) << "of " << got->width * got->height << " pixels; the largest difference " << worst;
  // And the overlay is where the test assumes: the fixture's shot has the tooth outside it.
  const nlohmann::json shot = readJson(kFixture / "shot-6s.json");
  EXPECT_GT(shot["tooth_centre_px"][0].get<double>(), kOverlayRight);
}

}  // namespace
}  // namespace dentsim
