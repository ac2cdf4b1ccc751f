// `run`, `demo` and `replay` spell --out, --overwrite and --shot alike (app/shared_options.h); replay's old -o/--output and --shot-at still work, each saying once that it is deprecated.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace dentsim {
namespace {

using test::readBytes;
using test::runDentsim;
using test::TempDir;

// How often `text` holds `part`.
int count(const std::string& text, const std::string& part) {
  int n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

// The help line of `option` in `help`, from the option's name to the end of its description (CLI11
// may break a long option's line after its type).
std::string helpOf(const std::string& help, const std::string& option) {
  const size_t at = help.find("  " + option + " ");
  if (at == std::string::npos) return "";
  size_t end = help.find('\n', at);
  // A continuation line is indented further than the option names.
  while (end != std::string::npos && help.compare(end + 1, 10, std::string(10, ' ')) == 0) end = help.find('\n', end + 1);
  return help.substr(at, end - at);
}

// One short session for the suite (as replay_window_cli_test.cpp records it): 2 s of the demo's path
// at level 7, no mirror, recorded headless.
class SharedOptionsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const test::NoLeakCheckForGpuChild no_leak_check;  // the run sets up its frames on the GPU
    demo_ = new test::CommandResult(runDentsim("run --headless --level 7 --mirror none --no-sound --demo-script --exit-after 2 --out " +
                                               dir_->file("rec")));
  }
  static void TearDownTestSuite() {
    delete demo_;
    delete dir_;
  }
  void SetUp() override { ASSERT_EQ(demo_->exit_code, 0) << demo_->output; }
  static std::string session() { return dir_->file("rec") + "/session.dses"; }
  static std::string file(const std::string& name) { return dir_->file(name); }

  static TempDir* dir_;
  static test::CommandResult* demo_;
};
TempDir* SharedOptionsCli::dir_ = nullptr;
test::CommandResult* SharedOptionsCli::demo_ = nullptr;

TEST_F(SharedOptionsCli, ReplayOutWritesTheFinalVolumeTheOldOutputWroteAndOnlyTheOldSaysItIsDeprecated) {
  const auto now = runDentsim("replay " + session() + " --headless --out " + file("new"));
  ASSERT_EQ(now.exit_code, 0) << now.output;
  EXPECT_EQ(now.output.find("deprecated"), std::string::npos) << now.output;
  const std::vector<uint8_t> final_volume = readBytes(file("new") + "/final.dvol");
  ASSERT_FALSE(final_volume.empty());
  EXPECT_EQ(final_volume, readBytes(file("rec") + "/final.dvol")) << "the replay ends where the recording did";
  for (const char* old : {"-o", "--output"}) {
    SCOPED_TRACE(old);
    const std::string path = file(std::string("old") + old + ".dvol");
    const auto then = runDentsim("replay " + session() + " --headless " + old + " " + path);
    ASSERT_EQ(then.exit_code, 0) << then.output;
    EXPECT_EQ(count(then.output, "dentsim replay: -o/--output FILE is deprecated; use --out DIR (writes DIR/final.dvol)\n"), 1)
        << then.output;
    EXPECT_EQ(count(then.output, "deprecated"), 1) << then.output;
    EXPECT_EQ(readBytes(path), final_volume) << "the old spelling writes what --out does";
  }
}

// A folder that holds a recording is kept, by replay as by run and demo, unless --overwrite.
TEST_F(SharedOptionsCli, ReplayKeepsAFolderWithARecordingUnlessOverwrite) {
  ASSERT_EQ(runDentsim("replay " + session() + " --headless --out " + file("again")).exit_code, 0);
  const auto second = runDentsim("replay " + session() + " --headless --out " + file("again"));
  test::expectCleanFailure(second, file("again"), "--overwrite");
  const auto overwritten = runDentsim("replay " + session() + " --headless --overwrite --out " + file("again"));
  EXPECT_EQ(overwritten.exit_code, 0) << overwritten.output;
  // The recording's own folder: replay refuses to write its final.dvol there without --overwrite too.
  test::expectCleanFailure(runDentsim("replay " + session() + " --headless --out " + file("rec")), file("rec"), "--overwrite");
}

TEST_F(SharedOptionsCli, ConflictingOrPointlessOutputOptionsAreRefused) {
  // --out and the old -o name the same thing two ways.
  const auto both = runDentsim("replay " + session() + " --headless --out " + file("both") + " --output " + file("both.dvol"));
  EXPECT_NE(both.exit_code, 0) << both.output;
  EXPECT_NE(both.output.find("dentsim: --output: names the final volume's file, --out its folder"), std::string::npos)
      << both.output;
  EXPECT_FALSE(std::filesystem::exists(file("both")));
  EXPECT_FALSE(std::filesystem::exists(file("both.dvol")));
  // A screenshot needs a folder: run and replay have no default one (demo's is dentsim-demo).
  test::expectCleanFailure(runDentsim("run --headless --shot 1"), "--shot", "give --out DIR");
  test::expectCleanFailure(runDentsim("replay " + session() + " --shot 1"), "--shot", "give --out DIR");
  // Replay's screenshots are the window's.
  test::expectCleanFailure(runDentsim("replay " + session() + " --headless --shot 1 --out " + file("shots")), "--shot",
                           "applies to the replay's window", file("shots"));
  // The old --shot-at is refused the same way, after saying it is deprecated.
  const auto old = runDentsim("replay " + session() + " --headless --shot-at 1 " + file("old.png"));
  EXPECT_NE(old.exit_code, 0) << old.output;
  EXPECT_EQ(count(old.output, "dentsim replay: --shot-at SECONDS FILE is deprecated; use --shot SECONDS (--out DIR)\n"), 1)
      << old.output;
  EXPECT_NE(old.output.find("dentsim: --shot-at: applies to the replay's window"), std::string::npos) << old.output;
}

// One definition (app/shared_options.h): each command's --help words --overwrite and --shot alike,
// and --out says what that command writes into it.
TEST(SharedOptionsHelp, RunDemoAndReplaySpellTheSharedOptionsAlike) {
  std::vector<std::string> overwrite, shot;
  for (const char* command : {"run", "demo", "replay"}) {
    SCOPED_TRACE(command);
    const auto help = runDentsim(std::string(command) + " --help");
    ASSERT_EQ(help.exit_code, 0) << help.output;
    EXPECT_NE(helpOf(help.output, "--out"), "") << help.output;
    overwrite.push_back(helpOf(help.output, "--overwrite"));
    shot.push_back(helpOf(help.output, "--shot"));
    EXPECT_NE(overwrite.back(), "") << help.output;
    EXPECT_NE(shot.back(), "") << help.output;
  }
  EXPECT_EQ(overwrite[0], overwrite[1]);
  EXPECT_EQ(overwrite[0], overwrite[2]);
  EXPECT_EQ(shot[0], shot[1]);
  EXPECT_EQ(shot[0], shot[2]);
}

}  // namespace
}  // namespace dentsim
