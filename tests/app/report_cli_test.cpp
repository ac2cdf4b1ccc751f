// Tests of `dentsim report`: a class of synthetic score reports and an outbox becomes one page with the counts, plots, pictures and points lost it should have; a report and its statement count once; bad input fails in one line and writes nothing, a bad outbox line costs only itself; a page over a picture it embeds is refused; each picture is embedded once and the pictures capped; Chromium renders the page.
#include <sys/time.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/png_file.h"
#include "test_support.h"

namespace dentsim {
namespace {

using test::runCommand;
using test::runDentsim;
using test::TempDir;

namespace fs = std::filesystem;

size_t countOf(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A picture of one colour, 32x16: the page shows it 360 px wide, so its colour fills a block.
void writePicture(const std::string& path, uint8_t r, uint8_t g, uint8_t b) {
  RgbImage image;
  image.width = 32;
  image.height = 16;
  for (int i = 0; i < image.width * image.height; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
  fs::create_directories(fs::path(path).parent_path());
  ASSERT_TRUE(writePng(path, image).ok());
}

// A score report as `dentsim score` writes it, trimmed to what the page reads, its file dated
// `time_s`; `extra` goes in at the end (",\"statement_id\":...").
void writeReport(const std::string& path, const std::string& task, double total, bool pulp, long time_s, const std::string& extra = "") {
  writeText(path, "{\"format\":\"dentsim-score\",\"version\":2,\"task\":{\"name\":\"" + task + "\",\"kind\":\"cavity\",\"title\":\"" + task +
                      " exercise\"},\"total\":" + std::to_string(total) + ",\"total_max\":100,\"pulp_exposed\":" +
                      (pulp ? "true" : "false") + extra + "}\n");
  const timeval times[2] = {{time_s, 0}, {time_s, 0}};
  ASSERT_EQ(::utimes(path.c_str(), times), 0) << path;
}

std::string statement(const std::string& verb, const std::string& task, double raw, const std::string& when,
                      const std::string& extensions) {
  return "{\"actor\":{\"objectType\":\"Agent\",\"name\":\"Carol <O'Brien>\",\"account\":{\"homePage\":\"https://school.example\","
         "\"name\":\"s03\"}},\"verb\":{\"id\":\"http://adlnet.gov/expapi/verbs/" + verb +
         "\"},\"object\":{\"id\":\"https://dentsim.example/tasks/" + task + "\",\"definition\":{\"name\":{\"en-US\":\"" + task +
         " exercise\"}}},\"result\":{\"score\":{\"raw\":" + std::to_string(raw) + ",\"scaled\":" + std::to_string(raw / 100) +
         "},\"success\":" + (verb == "passed" ? "true" : "false") + ",\"duration\":\"PT4M30S\",\"extensions\":{" + extensions +
         "}},\"timestamp\":\"" + when + "\"}\n";
}

// Alice's first try by its parts: the under-cut earned 5 of 25 (lost 20), the rest in full, 3 points
// off for force; 4:32 taken; 62.5 % of the surface within 0.2 mm.
constexpr const char* kAliceParts =
    ",\"components\":{\"undercut\":{\"points\":5,\"max\":25},\"overcut\":{\"points\":25,\"max\":25},"
    "\"tilt\":{\"points\":25,\"max\":25},\"time\":{\"points\":25,\"max\":25}},\"deductions\":{\"force\":{\"points\":3}},"
    "\"session\":{\"elapsed_s\":271.5},\"surface_agreement\":{\"band_mm\":0.2,\"within_percent\":62.5,\"beyond_percent\":20,"
    "\"short_percent\":17.5}";

// The class: alice tried caries removal twice (40, then 70), bob a class II once (55, pulp exposed),
// and carol's outbox holds a caries removal passed at 85 with its picture, a class II failed at 30,
// and a launch with no score. With a pass mark of 50: alice's 40, bob's pulp and carol's 30 are flagged.
class ReportCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeReport(file("class/alice/try1/score.json"), "caries_removal", 40, false, 1795760000, kAliceParts);
    writePicture(file("class/alice/try1/score.png"), 200, 30, 30);
    writeReport(file("class/alice/try2/score.json"), "caries_removal", 70, false, 1795763600);
    writePicture(file("class/alice/try2/score.png"), 30, 30, 200);
    writeReport(file("class/bob/try1/score.json"), "class2_cavity", 55, true, 1795762000);
    writePicture(file("class/bob/try1/score.png"), 30, 200, 30);
    writePicture(file("class/pics/carol.png"), 255, 0, 255);
    writeText(file("class/outbox.jsonl"),
              statement("passed", "caries_removal", 85, "2026-11-27T07:30:00Z",
                        "\"https://dentsim.example/xapi/pulp-exposed\":false,\"https://dentsim.example/xapi/score-picture\":\"pics/carol.png\"") +
                  statement("failed", "class2_cavity", 30, "2026-11-27T08:10:00Z", "\"https://dentsim.example/xapi/pulp-exposed\":false") +
                  "{\"actor\":{\"account\":{\"name\":\"s03\"}},\"verb\":{\"id\":\"http://adlnet.gov/expapi/verbs/launched\"},"
                  "\"object\":{\"id\":\"https://dentsim.example/tasks/caries_removal\"},\"timestamp\":\"2026-11-27T07:25:00Z\"}\n");
  }
  std::string file(const std::string& name) const { return dir_.file(name); }
  std::string inputs() const {
    return file("class/alice/try1/score.json") + " " + file("class/alice/try2/score.json") + " " + file("class/bob/try1/score.json") +
           " " + file("class/outbox.jsonl");
  }
  TempDir dir_;
};

TEST_F(ReportCli, ScoreReportsAndAnOutboxMakeOnePageWithPlotsTablesAndPictures) {
  // The pass mark before the inputs takes one value, leaving the inputs to be inputs.
  const auto r = runDentsim("report --pass-mark 50 " + inputs() + " -o " + file("report.html"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("5 attempts by 3 students at 2 tasks, 3 to look at, 4 pictures (1 statements without a score left out)"),
            std::string::npos)
      << r.output;
  const std::string html = readText(file("report.html"));
  EXPECT_EQ(countOf(html, "<svg class=\"progress\""), 2u);
  EXPECT_EQ(countOf(html, "<svg class=\"histogram\""), 2u);
  EXPECT_EQ(countOf(html, "<polyline"), 4u);  // caries: alice, carol; class II: bob, carol
  EXPECT_EQ(countOf(html, "<tr class=\"flagged\">"), 3u);
  EXPECT_EQ(countOf(html, "src=\"data:image/png;base64,"), 4u);
  EXPECT_EQ(countOf(html, "no picture"), 1u);  // carol's class II named none
  EXPECT_NE(html.find("Carol &lt;O&#39;Brien&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<O'Brien>"), std::string::npos);
  EXPECT_NE(html.find("below the pass mark of 50, failed"), std::string::npos);  // carol's 30
  EXPECT_NE(html.find("pulp exposed"), std::string::npos);                     // bob's
  EXPECT_NE(html.find(">4:30<"), std::string::npos);                            // carol's time taken
  // Alice's first try says why: the under-cut lost most, in its table row and its flagged row.
  EXPECT_EQ(countOf(html, "class=\"part lost lost-3\" data-part=\"undercut\" data-lost=\"20.00\""), 2u);
  EXPECT_EQ(countOf(html, "data-part="), 10u);  // five parts, twice
  EXPECT_NE(html.find(">undercut \u221220.0, force \u22123.0<"), std::string::npos);
  EXPECT_NE(html.find(">4:32<"), std::string::npos);
  EXPECT_NE(html.find(">62.5 % within \u00b10.20 mm<"), std::string::npos);
  // The others say nothing of their parts or agreement; bob's report nothing of its time either.
  EXPECT_EQ(countOf(html, "<td class=\"parts\">\u2014</td>"), 4u + 2u);  // all attempts, then the flagged
  EXPECT_EQ(countOf(html, "<td class=\"num\">\u2014</td>"), 2u + 4u);    // alice's and bob's times; four agreements

  // The class's folder gives the same page as its files named one by one.
  const auto folder = runDentsim("report " + file("class") + " --pass-mark 50 -o " + file("folder.html"));
  ASSERT_EQ(folder.exit_code, 0) << folder.output;
  EXPECT_EQ(readText(file("folder.html")), html);
}

TEST_F(ReportCli, BadInputFailsInOneLineAndLeavesTheLastPageAlone) {
  const std::string out = file("report.html");
  writeText(out, "the last good page");
  test::expectCleanFailure(runDentsim("report " + file("nope.json") + " -o " + out), "nope.json", "no such file");
  // A file where no line is a statement is not an outbox (a bad line among good ones is a warning).
  writeText(file("bad.jsonl"), "{\"actor\": oops}\n");
  test::expectCleanFailure(runDentsim("report " + inputs() + " " + file("bad.jsonl") + " -o " + out), "bad.jsonl:1", "malformed JSON");
  test::expectCleanFailure(runDentsim("report " + inputs() + " --pass-mark 150 -o " + out), "--pass-mark 150", "[0, 100]");
  EXPECT_EQ(readText(out), "the last good page");
  const std::string fresh = file("never.html");
  test::expectCleanFailure(runDentsim("report " + file("class/outbox.jsonl") + " " + file("missing/score.json") + " -o " + fresh),
                           "missing/score.json", "no such file", fresh);
}

// One attempt, two files: a score report carries its statement's id, so a folder holding the report
// and the outbox counts it once, as the statement's student; another id is another attempt.
TEST_F(ReportCli, AReportAndItsStatementCountOnceAndAnotherAttemptApart) {
  const std::string id = "0b6c6a57-2f7e-5b2e-9d1a-3c6f2e1d4a01";
  writeReport(file("lab/try1/score.json"), "class1_cavity", 52, false, 1795760000, ",\"statement_id\":\"" + id + "\"" + kAliceParts);
  writePicture(file("lab/try1/score.png"), 30, 200, 30);
  const std::string same = "{\"id\":\"" + id + "\"," + statement("failed", "class1_cavity", 52, "2026-11-27T07:30:00Z", "").substr(1);
  writeText(file("lab/outbox.jsonl"), same);
  const auto once = runDentsim("report " + file("lab") + " -o " + file("once.html"));
  ASSERT_EQ(once.exit_code, 0) << once.output;
  EXPECT_NE(once.output.find("1 attempts by 1 students at 1 tasks"), std::string::npos) << once.output;
  EXPECT_NE(once.output.find("(1 score reports and their statements counted once)"), std::string::npos) << once.output;
  const std::string html = readText(file("once.html"));
  EXPECT_NE(html.find("Carol &lt;O&#39;Brien&gt;"), std::string::npos);  // the statement's student, not the folder "lab"
  EXPECT_EQ(countOf(html, "src=\"data:image/png;base64,"), 1u);          // the report's picture
  EXPECT_EQ(countOf(html, "data-part=\"undercut\""), 2u);                // its parts, in both tables (it failed)
  EXPECT_NE(html.find("score.json, " + file("lab/outbox.jsonl") + ":1"), std::string::npos);

  const std::string other = "{\"id\":\"0b6c6a57-2f7e-5b2e-9d1a-3c6f2e1d4a02\"," +
                            statement("passed", "class1_cavity", 80, "2026-11-28T07:30:00Z", "").substr(1);
  writeText(file("lab/outbox.jsonl"), same + other);
  const auto twice = runDentsim("report " + file("lab") + " -o " + file("twice.html"));
  ASSERT_EQ(twice.exit_code, 0) << twice.output;
  EXPECT_NE(twice.output.find("2 attempts by 1 students at 1 tasks"), std::string::npos) << twice.output;
}

// One bad line in an outbox (a torn write, a hand edit) costs only itself: the report is made from
// the rest, with one warning naming the file and the line.
TEST_F(ReportCli, ABadOutboxLineIsLeftOutWithOneWarning) {
  const std::string outbox = file("torn/outbox.jsonl");
  writeText(outbox, statement("passed", "caries_removal", 85, "2026-11-27T07:30:00Z", "") + "{\"actor\": oops}\n" +
                        statement("failed", "class2_cavity", 30, "2026-11-27T08:10:00Z", "") + "{\"id\":\"torn");
  const auto r = runDentsim("report " + outbox + " -o " + file("torn.html"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("dentsim: warning: " + outbox + ":2: not a JSON statement (malformed JSON); line left out\n"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("dentsim: warning: " + outbox + ":4: not a JSON statement (malformed JSON); line left out\n"), std::string::npos)
      << r.output;
  EXPECT_EQ(countOf(r.output, "dentsim: warning:"), 2u) << r.output;
  EXPECT_NE(r.output.find("wrote " + file("torn.html") + ": 2 attempts by 1 students at 2 tasks"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(file("torn.html")));
}

// The pictures the page embeds are inputs: a page written over one, by its name or a link to it, is
// refused in one line and the picture is left as it was.
TEST_F(ReportCli, APageOverAPictureItEmbedsIsRefused) {
  const std::string picture = file("class/alice/try1/score.png");
  const std::string before = readText(picture);
  test::expectCleanFailure(runDentsim("report " + file("class") + " -o " + picture), picture, "is the same file as the input");
  EXPECT_EQ(readText(picture), before);
  fs::create_hard_link(picture, file("alias.html"));
  test::expectCleanFailure(runDentsim("report " + file("class") + " -o " + file("alias.html")), "alias.html",
                           "is the same file as the input " + picture);
  EXPECT_EQ(readText(picture), before);
  // Carol's picture, named by her outbox's statement, the same.
  test::expectCleanFailure(runDentsim("report " + file("class") + " -o " + file("class/pics/carol.png")), "carol.png",
                           "is the same file as the input");
}

// A picture of noise, `side` px square: PNG cannot compress it, so its file is about 3 x side^2 bytes.
void writeNoise(const std::string& path, int side, uint32_t seed) {
  RgbImage image;
  image.width = image.height = side;
  for (int i = 0; i < 3 * side * side; ++i) {
    seed = seed * 1664525u + 1013904223u;
    image.rgb.push_back(uint8_t(seed >> 24));
  }
  fs::create_directories(fs::path(path).parent_path());
  ASSERT_TRUE(writePng(path, image).ok());
}

// The page's size is capped: an outbox naming one picture 40 times embeds it once (the others link
// to it), and past the cap on embedded bytes a picture is linked by its path, with one warning; a
// copy of an embedded picture under another name costs nothing.
TEST_F(ReportCli, EachPictureIsEmbeddedOnceAndThePagesPicturesAreCapped) {
  writeNoise(file("big/pics/noise.png"), 128, 1);  // about 48 KiB
  const uint64_t picture_bytes = fs::file_size(file("big/pics/noise.png"));
  std::string lines;
  for (int i = 0; i < 40; ++i)
    lines += statement("passed", "caries_removal", 60 + i % 30, "2026-11-27T07:" + std::string(i < 10 ? "0" : "") + std::to_string(i) + ":00Z",
                       "\"https://dentsim.example/xapi/score-picture\":\"pics/noise.png\"");
  writeText(file("big/outbox.jsonl"), lines);
  const auto r = runDentsim("report " + file("big/outbox.jsonl") + " -o " + file("big.html"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = readText(file("big.html"));
  EXPECT_EQ(countOf(html, "src=\"data:image/png;base64,"), 1u);
  EXPECT_EQ(countOf(html, "<a class=\"samepic\" href=\"#pic-0\">"), 39u);
  EXPECT_LT(html.size(), 2 * picture_bytes + 200000) << "40 copies would be " << 40 * picture_bytes * 4 / 3;

  // Three pictures in time order: noise, other noise, and a copy of the first under another name.
  // The cap holds one: the first is embedded, the second linked by its path, the copy shown by a
  // link to the first.
  writeNoise(file("cap/pics/one.png"), 128, 1);
  writeNoise(file("cap/pics/two.png"), 128, 2);
  fs::copy_file(file("cap/pics/one.png"), file("cap/pics/copy.png"));
  writeText(file("cap/outbox.jsonl"),
            statement("passed", "caries_removal", 70, "2026-11-27T07:00:00Z", "\"https://dentsim.example/xapi/score-picture\":\"pics/one.png\"") +
                statement("passed", "caries_removal", 71, "2026-11-27T07:01:00Z", "\"https://dentsim.example/xapi/score-picture\":\"pics/two.png\"") +
                statement("passed", "caries_removal", 72, "2026-11-27T07:02:00Z", "\"https://dentsim.example/xapi/score-picture\":\"pics/copy.png\""));
  const auto capped = runCommand("DENTSIM_REPORT_PICTURE_CAP_BYTES=" + std::to_string(picture_bytes + 1000) + " " +
                                 std::string(DENTSIM_BINARY) + " report " + file("cap/outbox.jsonl") + " -o " + file("cap.html"));
  ASSERT_EQ(capped.exit_code, 0) << capped.output;
  EXPECT_EQ(countOf(capped.output, "dentsim: warning:"), 1u) << capped.output;
  EXPECT_NE(capped.output.find("1 picture(s) past the " + std::to_string(picture_bytes + 1000) +
                               " bytes of pictures a page embeds are linked by their path instead (the first: " + file("cap/pics/two.png") + ")"),
            std::string::npos)
      << capped.output;
  const std::string page = readText(file("cap.html"));
  EXPECT_EQ(countOf(page, "src=\"data:image/png;base64,"), 1u);
  EXPECT_EQ(countOf(page, "<a class=\"samepic\" href=\"#pic-0\">"), 1u);
  EXPECT_EQ(countOf(page, "<a class=\"filepic\" href=\"file://" + file("cap/pics/two.png") + "\">"), 1u);
  EXPECT_EQ(countOf(page, "no picture"), 0u);
  // Without the lowered cap all three are shown, two embedded.
  const auto whole = runDentsim("report " + file("cap/outbox.jsonl") + " -o " + file("whole.html"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_EQ(countOf(readText(file("whole.html")), "src=\"data:image/png;base64,"), 2u);
}

// Chromium renders the page: the DOM it built holds the plots' lines and bars, the pictures and the
// marks of the points lost, and its screenshot shows the first student's line colour, the histogram
// bars, carol's magenta picture and alice's under-cut mark.
TEST_F(ReportCli, ChromiumRendersThePlotsAndPictures) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (" << chromium << "): scripts/install-deps.sh installs it";
  const std::string page = file("report.html");
  const auto r = runDentsim("report " + inputs() + " --pass-mark 50 -o " + page);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // No sandbox: the tests may run as root in a container; the profile is the test's own.
  const std::string browser = std::string("timeout 120 ") + chromium +
                              " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run --user-data-dir=" +
                              file("profile") + " --force-color-profile=srgb --hide-scrollbars --window-size=1280,4000 ";
  const std::string shot = file("shot.png");
  const auto dom = runCommand(browser + "--dump-dom file://" + page);
  ASSERT_EQ(dom.exit_code, 0) << dom.output;
  EXPECT_EQ(countOf(dom.output, "<svg class=\"progress\""), 2u);
  EXPECT_EQ(countOf(dom.output, "<polyline"), 4u);
  EXPECT_EQ(countOf(dom.output, "<rect class=\"bar\""), 5u);  // caries 40, 70, 85; class II 30, 55
  EXPECT_EQ(countOf(dom.output, "<img alt="), 4u);
  EXPECT_EQ(countOf(dom.output, "data-part="), 10u);  // alice's first try: five parts, in both tables
  EXPECT_EQ(countOf(dom.output, "<span class=\"part lost lost-3\" data-part=\"undercut\""), 2u);
  EXPECT_EQ(countOf(dom.output, "role=\"img\" aria-label=\"parts: undercut 5.0 of 25;"), 2u);
  const auto taken = runCommand(browser + "--screenshot=" + shot + " file://" + page);
  ASSERT_EQ(taken.exit_code, 0) << taken.output;
  auto image = readPng(shot);
  ASSERT_TRUE(image.ok()) << image.message() << "\n" << taken.output;
  size_t white = 0, line = 0, bar = 0, magenta = 0, undercut = 0;
  auto near = [](std::array<uint8_t, 3> p, int red, int green, int blue) {
    return std::abs(p[0] - red) <= 6 && std::abs(p[1] - green) <= 6 && std::abs(p[2] - blue) <= 6;
  };
  for (int y = 0; y < image->height; ++y)
    for (int x = 0; x < image->width; ++x) {
      const auto p = image->pixel(x, y);
      white += near(p, 255, 255, 255);
      line += near(p, 0x1f, 0x77, 0xb4);   // studentColour(0)
      bar += near(p, 0x4a, 0x7f, 0xb5);    // the bars' fill
      magenta += near(p, 255, 0, 255);     // carol's picture
      undercut += near(p, 0xdd, 0x5a, 0x2b);  // a part that lost up to four fifths
    }
  const size_t all = size_t(image->width) * size_t(image->height);
  EXPECT_LT(white, all * 98 / 100) << "the screenshot is blank";
  EXPECT_GT(line, 100u);
  EXPECT_GT(bar, 2000u);
  EXPECT_GT(magenta, 20000u);  // 360 x 180 px less the frame
  EXPECT_GT(undercut, 400u);   // three 14 px marks: alice's two rows and the key
}

}  // namespace
}  // namespace dentsim
