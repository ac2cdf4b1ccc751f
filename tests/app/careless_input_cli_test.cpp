// Tests of issue 27's command-line part on the real binary: every number refused by name when it is NaN, infinite or out of range; options that cannot apply refused with the reason; no command writing over its own input; output folders holding a recording kept; a task's files confined to its folder; export saying why it cannot write.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/text_escape.h"
#include "io/dicom_series.h"
#include "io/grey_image.h"
#include "io/stl_file.h"
#include "test_meshes.h"
#include "test_support.h"
#include "unprivileged.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::readBytes;
using test::runDentsim;
using test::TempDir;
using test::writeBytes;

// A refusal at parse time: one line "dentsim: --option: ...", non-zero exit, the reason's key
// words, nothing run, and not a wall of digits.
void expectRefusedOption(const CommandResult& r, const std::string& option, const std::string& problem) {
  test::expectCleanFailure(r, "dentsim: " + option + ": ", problem);
  EXPECT_LT(r.output.size(), 200u) << r.output;
}

// A 10 mm cube, voxelized on the CPU at level 5 (32^3): a real .dvol in well under a second.
class CarelessInputCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeBytes(stl(), encodeStlBinary(test::box({0, 0, 0}, {10, 10, 10}), "cube"));
    const CommandResult made = runDentsim("voxelize --tooth " + stl() + " --level 5 --cpu -o " + dvol());
    ASSERT_EQ(made.exit_code, 0) << made.output;
  }
  std::string stl() const { return dir_.file("t.stl"); }
  std::string dvol() const { return dir_.file("t.dvol"); }
  // The one-line refusal to write over an input: both paths named, the input's bytes unchanged.
  void expectInputKept(const CommandResult& r, const std::string& output, const std::string& input,
                       const std::vector<uint8_t>& before) {
    test::expectCleanFailure(r, output, "is the same file as the input " + input);
    EXPECT_EQ(readBytes(input), before) << input;
  }
  TempDir dir_;
};

// The issue's cases and their kin: NaN, infinities, 1e300 and values past the physical range are
// refused by name before anything runs (a run that took them never ended, or ran past 120 s).
TEST_F(CarelessInputCli, EveryNumberIsFiniteAndInRangeOrRefusedByName) {
  struct Case {
    std::string args, option, problem;
  };
  const std::string tooth = "voxelize --tooth " + stl() + " -o " + dir_.file("never.dvol");
  const std::vector<Case> cases = {
      {"run --headless --exit-after nan", "--exit-after", "not a finite number"},
      {"run --headless --exit-after inf", "--exit-after", "not a finite number"},
      {"run --headless --exit-after 1e300", "--exit-after", "1e+300 is out of range (expected [0, 86400] s)"},
      {"run --headless --demo-script --fps 1e9", "--fps", "out of range (expected [1, 1000] frames/s)"},
      {"run --headless --demo-script --fps 0.001", "--fps", "out of range"},
      {"run --headless --demo-script --reach nan", "--reach", "not a finite number"},
      {"run --headless --demo-script --wander=-inf", "--wander", "not a finite number"},
      {"run --headless --demo-script --shot nan", "--shot", "not a finite number"},
      {"run --headless --demo-script --frame-every 1e300", "--frame-every", "out of range"},
      {"demo --headless --exit-after nan", "--exit-after", "not a finite number"},
      {tooth + " --voxel-size nan", "--voxel-size", "not a finite number"},
      {tooth + " --voxel-size 1e300", "--voxel-size", "1e+300 is out of range (expected [0.001, 10] mm)"},
      {tooth + " --scale inf", "--scale", "not a finite number"},
      {tooth + " --crown-axis 0,0,nan", "--crown-axis", "not a finite number"},
      {"voxelize --labels x.nii.gz --label-map 1=dentin --fill-enclosed pulp --seal-mm nan -o y.dvol", "--seal-mm",
       "not a finite number"},
      {"make-tooth --grid nan --out " + dir_.file("never"), "--grid", "not a finite number"},
      {"task new --tooth builtin:molar --pass-mark nan -o " + dir_.file("never.json"), "--pass-mark", "not a finite number"},
      {"task new --tooth builtin:molar --view-elevation 1e9 -o " + dir_.file("never.json"), "--view-elevation",
       "out of range"},
      {"replay " + dir_.file("s.dses") + " --seek-at nan 1", "--seek-at", "not a finite number"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    expectRefusedOption(runDentsim(c.args), c.option, c.problem);
  }
  EXPECT_FALSE(fs::exists(dir_.file("never.dvol")));
  EXPECT_FALSE(fs::exists(dir_.file("never.json")));
  EXPECT_FALSE(fs::exists(dir_.file("never")));
}

// Options the chosen mode cannot use fail in one line with the reason, before anything runs.
TEST_F(CarelessInputCli, AnOptionThatCannotApplyIsRefusedWithTheReason) {
  struct Case {
    std::string args, names, problem;
  };
  const std::string never = dir_.file("never");
  writeBytes(dir_.file("p.csv"), {'t', '\n'});
  const std::vector<Case> cases = {
      {"voxelize --tooth " + stl() + " --voxel-size 0.5 --level 6 -o " + never, "--voxel-size", "give one of the two"},
      {"voxelize --tooth " + stl() + " --seal-mm 0.3 -o " + never, "--seal-mm", "no --fill-enclosed"},
      {"voxelize --enamel " + stl() + " --tooth-material pulp -o " + never, "--tooth-material", "no --tooth"},
      {"voxelize --labels x.nii.gz --label-map 1=dentin --units cm -o " + never, "--units", "applies to STL layers"},
      {"run --headless --demo-script --pen-script " + dir_.file("p.csv") + " --out " + never, "--pen-script",
       "give one of the two"},
      {"run --headless --tooth " + dvol() + " --level 9 --exit-after 1 --out " + never, "--level",
       "applies only to a built-in tooth"},
      {"run --headless --demo-script --no-sound --audio-out " + dir_.file("s.wav") + " --out " + never, "--audio-out",
       "--no-sound"},
      {"run --headless --demo-script --bur mirror_size4 --out " + never, "--bur", "\"mirror_size4\" is a mirror, not a bur"},
      {"run --headless --demo-script --mirror-tool round_bur_010 --out " + never, "--mirror-tool", "not a mirror"},
      {"run --headless --demo-script --bur no_such_bur --out " + never, "--bur", "not in the tool catalog"},
      {"run --headless --attempt trench --exit-after 1 --out " + never, "--attempt", "--demo-script"},
      {"run --headless --demo-script --recorded-rpm 30000 --out " + never, "--recorded-rpm", "--turbine-wav"},
      {"run --headless --demo-script --turbine-wav " + dir_.file("t.wav") + " --out " + never, "--turbine-wav",
       "a headless run plays no sound"},
      {"run --headless --demo-script --guide-stiffness 2 --out " + never, "--guide-stiffness", "--guide"},
      {"run --headless --wander 1 --exit-after 1 --out " + never, "--wander", "pen script"},
      {"run --headless --score-at-end --exit-after 1 --out " + never, "--score-at-end", "pen script ends"},
      {"run --exit-at-end --exit-after 1 --out " + never, "--exit-at-end", "pen script ends"},
      {"demo --headless --stay --out " + never, "--stay", "--headless"},
      {"demo --headless --mirror round_bur_010 --out " + never, "--mirror", "not a mirror"},
      {"replay " + dir_.file("s.dses") + " --headless --speed 2", "--speed", "window"},
      {"replay " + dir_.file("s.dses") + " --audio-out " + dir_.file("s.wav") + " --width 640", "--width", "window"},
      {"task new --tooth builtin:molar --bur mirror_size4 -o " + dir_.file("t.json"), "--bur", "is a mirror, not a bur"},
      {"task new --tooth builtin:molar --kind cavity --failure-s 900 -o " + dir_.file("t.json"), "--failure-s",
       "caries task"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    test::expectCleanFailure(runDentsim(c.args), c.names, c.problem);
  }
  EXPECT_FALSE(fs::exists(never));
  EXPECT_FALSE(fs::exists(dir_.file("s.wav")));
  EXPECT_FALSE(fs::exists(dir_.file("t.json")));
}

// `voxelize --tooth t.stl -o t.stl` and its kin: the output is the input itself, a symbolic link to
// it or a hard link to it; each is refused naming both paths, and the input keeps its bytes.
TEST_F(CarelessInputCli, NoCommandWritesOverItsOwnInputNorALinkToIt) {
  const std::vector<uint8_t> stl_bytes = readBytes(stl()), dvol_bytes = readBytes(dvol());
  fs::create_symlink(stl(), dir_.file("sym.stl"));
  fs::create_hard_link(dvol(), dir_.file("hard.ply"));  // a .dvol under a mesh's name
  fs::create_hard_link(dvol(), dir_.file("hard.nii"));  // and under a label volume's
  expectInputKept(runDentsim("voxelize --tooth " + stl() + " --level 5 --cpu -o " + stl()), stl(), stl(), stl_bytes);
  expectInputKept(runDentsim("voxelize --tooth " + stl() + " --level 5 --cpu -o " + dir_.file("sym.stl")),
                  dir_.file("sym.stl"), stl(), stl_bytes);
  expectInputKept(runDentsim("voxelize --tooth " + stl() + " --level 5 --cpu --frame-of " + dvol() + " -o " + dvol()), dvol(),
                  dvol(), dvol_bytes);
  expectInputKept(runDentsim("score --task caries --initial " + dvol() + " --final " + dvol() + " -o " + dvol() +
                             " --png " + dir_.file("x.png")),
                  dvol(), dvol(), dvol_bytes);
  expectInputKept(runDentsim("score --task caries --initial " + dvol() + " --final " + dvol() + " -o " +
                             dir_.file("x.json") + " --png " + dvol()),
                  dvol(), dvol(), dvol_bytes);
  expectInputKept(runDentsim("mesh " + dvol() + " --cpu -o " + dir_.file("hard.ply")), dir_.file("hard.ply"), dvol(),
                  dvol_bytes);
  expectInputKept(runDentsim("export " + dvol() + " -o " + dir_.file("hard.nii")), dir_.file("hard.nii"), dvol(),
                  dvol_bytes);
  // The run's and the demo's inputs against their outputs: a recording as the turbine's sound.
  writeBytes(dir_.file("t.wav"), {'R', 'I', 'F', 'F'});
  const std::vector<uint8_t> wav = readBytes(dir_.file("t.wav"));
  expectInputKept(runDentsim("run --headless --demo-script --turbine-wav " + dir_.file("t.wav") + " --audio-out " +
                             dir_.file("t.wav") + " --out " + dir_.file("run")),
                  dir_.file("t.wav"), dir_.file("t.wav"), wav);
  EXPECT_FALSE(fs::exists(dir_.file("x.json")));
  EXPECT_FALSE(fs::exists(dir_.file("x.png")));
  EXPECT_FALSE(fs::exists(dir_.file("run")));
}

// `run --out DIR` and `demo --out DIR` keep a recording already there, finished or cut off by a
// crash, unless --overwrite; --overwrite still never writes over a file the run reads.
TEST_F(CarelessInputCli, AnOutputFolderHoldingARecordingIsKeptUnlessOverwriteIsGiven) {
  const std::string out = dir_.file("rec");
  fs::create_directories(out);
  for (const char* name : {"session.dses.part", "initial.dvol"}) {
    SCOPED_TRACE(name);
    fs::remove_all(out);
    fs::create_directories(out);
    writeBytes(out + "/" + name, {'k', 'e', 'e', 'p'});
    for (const std::string cmd : {"run --headless --demo-script --level 6 --no-sound", "demo --headless --level 6 --no-sound"}) {
      const CommandResult r = runDentsim(cmd + " --out " + out);
      test::expectCleanFailure(r, out + ": already holds a recording (" + name + ")", "--overwrite");
      EXPECT_EQ(readBytes(out + "/" + name), (std::vector<uint8_t>{'k', 'e', 'e', 'p'}));
    }
  }
  // With --overwrite the folder may be reused, but the run's own tooth there is still an input.
  const std::string tooth = out + "/initial.dvol";
  fs::copy_file(dvol(), tooth, fs::copy_options::overwrite_existing);
  const std::vector<uint8_t> before = readBytes(tooth);
  expectInputKept(runDentsim("run --headless --demo-script --tooth " + tooth + " --overwrite --no-sound --out " + out), tooth,
                  tooth, before);
}

// A task names files only in its own folder: `task new` copies a tooth from elsewhere beside the
// task (and refuses to replace another file of that name), and a task file naming ../x or an
// absolute path is refused without reading it.
TEST_F(CarelessInputCli, ATaskNamesOnlyFilesInItsOwnFolder) {
  const std::string course = dir_.file("course");
  fs::create_directories(course);
  const CommandResult made = runDentsim("task new --kind cavity --tooth " + dvol() + " -o " + course + "/t.json");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  EXPECT_EQ(readBytes(course + "/t.dvol"), readBytes(dvol()));
  std::ifstream in(course + "/t.json");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"tooth\": \"t.dvol\""), std::string::npos) << text;
  // Another tooth of the same name already there is kept, and the task is not written.
  writeBytes(course + "/t.dvol", {'o', 't', 'h', 'e', 'r'});
  const CommandResult clash = runDentsim("task new --kind cavity --tooth " + dvol() + " -o " + course + "/u.json");
  EXPECT_EQ(clash.exit_code, 1) << clash.output;
  EXPECT_NE(clash.output.find("dentsim: --tooth: " + course + "/t.dvol: exists and differs from " + dvol() +
                              ", which the task would copy there: rename one\n"),
            std::string::npos)
      << clash.output;
  EXPECT_EQ(readBytes(course + "/t.dvol"), (std::vector<uint8_t>{'o', 't', 'h', 'e', 'r'}));
  EXPECT_FALSE(fs::exists(course + "/u.json"));
  // A secret beside the course, which the task must not reach; its first bytes must never show.
  std::ofstream(dir_.file("secret.json")) << "Zebra-secret";
  for (const std::string& named : {std::string("../secret.json"), dir_.file("secret.json")}) {
    SCOPED_TRACE(named);
    std::ofstream(course + "/bad.json")
        << R"({"format":"dentsim-task","version":2,"name":"bad","kind":"caries","tooth":")" << named
        << R"(","tools":{"drill":"round_bur_010"},"target_s":300,"failure_s":900,"force_error_n":3})";
    const CommandResult r = runDentsim("task check " + course + "/bad.json");
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("a file names only files in its own folder or below it"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Zebra"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("'Z'"), std::string::npos) << r.output;
  }
}

// export says why it cannot write: here a folder the user may not write to (run as nobody, since
// the tests run as root, whom every mode lets in).
TEST_F(CarelessInputCli, ExportSaysWhyItCannotWrite) {
  if (std::string why = test::whyNotNobody(); !why.empty()) GTEST_SKIP() << why;
  if (!test::haveSetpriv()) GTEST_SKIP() << "setpriv is not installed";
  test::letEveryoneIn(dir_.path());
  ::chmod(dvol().c_str(), 0644);
  const std::string out = dir_.file("labels.nii.gz");
  const CommandResult r = test::runCommand(test::asNobody() + DENTSIM_BINARY + " export " + dvol() + " -o " + out);
  // libnifti prints its own "** ERROR" line first; dentsim's line says why.
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("dentsim: " + out + ": cannot write the NIfTI file (" + dir_.path().string() +
                          ": Permission denied)\n"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// A file name is data: one holding a newline and a terminal escape (ESC [31m, red) is echoed
// escaped, so each error stays one line and cannot drive the terminal. Issue 40.
TEST_F(CarelessInputCli, ANameWithANewlineOrAnEscapeStaysOneEscapedLine) {
  const std::string weird = dir_.file("a\nb\x1b[31mred");
  fs::create_directories(weird);
  const std::string stl_in = weird + "/in\n\x1b[31m.stl";
  fs::copy_file(stl(), stl_in);
  const std::vector<uint8_t> before = readBytes(stl_in);
  // sh -c takes newline and ESC inside single quotes as they are.
  const auto quoted = [](const std::string& path) { return "'" + path + "'"; };
  const std::vector<std::string> commands = {
      "voxelize --tooth " + quoted(weird + "/missing\n\x1b[31m.stl") + " --level 5 --cpu -o " + dir_.file("x.dvol"),
      "voxelize --tooth " + quoted(stl_in) + " --level 5 --cpu -o " + quoted(stl_in),
      "voxelize --tooth " + stl() + " --level 5 --cpu -o " + quoted(weird + "/no\n\x1b[31mfolder/x.dvol"),
      "voxelize --tooth " + stl() + " --units " + quoted("m\n\x1b[31mm") + " -o " + dir_.file("x.dvol"),
      "info " + quoted(weird + "/t\n\x1b[31m.dvol"),
      "mesh " + quoted(weird + "/t\n\x1b[31m.dvol") + " --cpu -o " + dir_.file("x.ply"),
      "replay " + quoted(weird + "/s\n\x1b[31m.dses") + " --headless",
  };
  for (const std::string& c : commands) {
    SCOPED_TRACE(escapeControl(c, 1000));
    // stderr alone: what a command prints on stdout before it fails is not the error line.
    const CommandResult r = test::runCommand("{ " + std::string(DENTSIM_BINARY) + " " + c + " >/dev/null; }");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\\x1b[31m"), std::string::npos) << r.output;  // named, escaped
  }
  EXPECT_EQ(readBytes(stl_in), before);
  EXPECT_FALSE(fs::exists(dir_.file("x.dvol")));
}

// `voxelize --dicom DIR -o DIR/slice-0001.dcm` once replaced a slice of its own series and exited
// 0. Any output inside an input folder is refused in one line, and the series is left as it was.
TEST_F(CarelessInputCli, AnOutputInsideTheInputSeriesFolderIsRefused) {
  GreyImage scan;  // 4 x 4 x 3 voxels of 1 mm: three slices, enough to be a series
  scan.dims = {4, 4, 3};
  scan.pitch_mm = {1.0, 1.0, 1.0};
  scan.scanner_from_voxel = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  scan.values.assign(size_t(scan.voxelCount()), 1000.0f);
  scan.unit = GreyUnit::Hounsfield;
  const std::string series = dir_.file("series");
  auto files = writeDicomSeries(series, scan);
  ASSERT_TRUE(files.ok()) << files.message();
  ASSERT_EQ(files->size(), 3u);
  const std::string slice = series + "/slice-0001.dcm";
  ASSERT_TRUE(fs::exists(slice));
  const std::vector<uint8_t> before = readBytes(slice);
  fs::create_symlink(series, dir_.file("link"));
  for (const std::string& out : {slice, series + "/new.dvol", series + "/./sub/../slice-0002.dcm",
                                 dir_.file("link") + "/slice-0001.dcm"}) {
    SCOPED_TRACE(out);
    const CommandResult r = runDentsim("voxelize --dicom " + series + " --level 5 -o " + out);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    test::expectCleanFailure(r, out, "lies inside the input folder " + series);
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  EXPECT_EQ(readBytes(slice), before);
  EXPECT_FALSE(fs::exists(series + "/new.dvol"));
  EXPECT_EQ(std::distance(fs::directory_iterator(series), fs::directory_iterator()), 3);
  // A folder beside the series whose name begins with the series' name is not inside it.
  const CommandResult beside = runDentsim("voxelize --dicom " + series + " --level 5 -o " + dir_.file("series2/x.dvol"));
  EXPECT_EQ(beside.output.find("lies inside"), std::string::npos) << beside.output;
}

// `score --student NAME` checks the name before the teeth are read or scored: with a tooth that does
// not exist the refusal still names --student (scoring first would have named the tooth), and with
// real teeth nothing is written, neither the report, nor the picture, nor an outbox.
TEST_F(CarelessInputCli, ScoreRefusesABadStudentNameBeforeScoring) {
  const std::string report = dir_.file("s.json"), png = dir_.file("s.png"), outbox = dir_.file("outbox.jsonl");
  // The default config and outbox places inside the test's folder, so that a config in the user's home plays no part.
  const std::string dentsim = "DENTSIM_CONFIG= XDG_CONFIG_HOME=" + dir_.file("xdg-config") + " XDG_DATA_HOME=" +
                              dir_.file("xdg-data") + " " + std::string(DENTSIM_BINARY);
  const std::string bad_name = " --student 's1\u202e' --outbox " + outbox;
  test::expectCleanFailure(test::runCommand(dentsim + " score --task caries --initial " + dir_.file("missing.dvol") + " --final " +
                                            dvol() + " -o " + report + bad_name),
                           "--student: \"s1\\u202e\"", "bidirectional control character", report);
  test::expectCleanFailure(test::runCommand(dentsim + " score --task caries --initial " + dvol() + " --final " + dvol() + " -o " +
                                            report + " --png " + png + " --student " + std::string(1000, 's') + " --outbox " + outbox),
                           "--student:", "longer than 64 bytes", report);
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(outbox));
  // The same command with a good name scores and records: the refusal was the name's alone.
  const CommandResult good = test::runCommand(dentsim + " score --task caries --initial " + dvol() + " --final " + dvol() + " -o " +
                                              report + " --png " + png + " --student s1 --outbox " + outbox);
  ASSERT_EQ(good.exit_code, 0) << good.output;
  EXPECT_TRUE(fs::exists(report));
  EXPECT_TRUE(fs::exists(outbox));
}

}  // namespace
}  // namespace dentsim
