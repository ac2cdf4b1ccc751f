// The learning records' config file: every key read, a relative outbox found beside the file, and each mistake named by file and key.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "io/learning_config.h"
#include "test_support.h"

namespace dentsim {
namespace {

TEST(LearningConfig, ReadsEveryKeyAndPutsARelativeOutboxBesideTheFile) {
  test::TempDir dir;
  const std::string path = dir.file("learning.json");
  std::ofstream(path) << R"({"student": "s1001", "student_name": "Ada", "course": "cons-101",
    "lrs": "https://lrs.school.example/xapi", "username": "lab", "password": "secret",
    "home_page": "https://school.example", "activity_base": "https://school.example/xapi",
    "language": "en-GB", "outbox": "records/outbox.jsonl"})";
  auto c = loadLearningConfig(path);
  ASSERT_TRUE(c.ok()) << c.message();
  EXPECT_EQ(*c->student, "s1001");
  EXPECT_EQ(*c->student_name, "Ada");
  EXPECT_EQ(*c->course, "cons-101");
  EXPECT_EQ(*c->lrs, "https://lrs.school.example/xapi");
  EXPECT_EQ(*c->username, "lab");
  EXPECT_EQ(*c->password, "secret");
  EXPECT_EQ(*c->home_page, "https://school.example");
  EXPECT_EQ(*c->activity_base, "https://school.example/xapi");
  EXPECT_EQ(*c->language, "en-GB");
  EXPECT_EQ(*c->outbox, dir.file("records/outbox.jsonl"));
  auto empty = parseLearningConfig("{}", "e.json");
  ASSERT_TRUE(empty.ok());
  EXPECT_FALSE(empty->student.has_value());
}

TEST(LearningConfig, MistakesNameTheFileAndTheKey) {
  auto error = [](const std::string& text) { return parseLearningConfig(text, "l.json").message(); };
  EXPECT_EQ(error(R"({"student": 7})"), "l.json: student: expected a string, got number");
  EXPECT_EQ(error(R"({"course": "my course"})"),
            "l.json: course: \"my course\" is not a plain name (letters, digits, '_', '-', '.')");
  EXPECT_EQ(error(R"({"lrs": "lrs.school.example"})"), "l.json: lrs: \"lrs.school.example\" does not start with http:// or https://");
  EXPECT_EQ(error(R"({"outbox": ""})"), "l.json: outbox: empty");
  EXPECT_EQ(error(R"({"student": "a", "student": "b"})"), "l.json: student: repeated key");
  EXPECT_EQ(error(R"({"studnet": "a"})").rfind("l.json: studnet: unknown key", 0), 0u) << error(R"({"studnet": "a"})");
  EXPECT_EQ(error("[1]").rfind("l.json: ", 0), 0u);
  EXPECT_EQ(loadLearningConfig("/nonexistent/learning.json").message().rfind("/nonexistent/learning.json: ", 0), 0u);
}

TEST(LearningConfig, StudentNamesWithControlOrBidiCharactersOrTooLongAreRefused) {
  EXPECT_EQ(studentNameProblem("s1001", kMaxStudentIdBytes), "");
  EXPECT_EQ(studentNameProblem("Zo\u00eb \u05d3\u05e0\u05d4", kMaxStudentNameBytes), "");  // accents and Hebrew are names
  EXPECT_EQ(studentNameProblem("", kMaxStudentIdBytes), "is empty");
  EXPECT_EQ(studentNameProblem(std::string(65, 'a'), kMaxStudentIdBytes), "is longer than 64 bytes");
  EXPECT_EQ(studentNameProblem("a\tb", kMaxStudentIdBytes), "holds a control character");
  EXPECT_EQ(studentNameProblem("a\x1b[2Jb", kMaxStudentIdBytes), "holds a control character");
  EXPECT_EQ(studentNameProblem("a\u0085b", kMaxStudentIdBytes), "holds a control character");  // C1 NEL
  EXPECT_EQ(studentNameProblem("a\u202eb", kMaxStudentIdBytes), "holds a bidirectional control character");  // RLO
  EXPECT_EQ(studentNameProblem("a\u200fb", kMaxStudentIdBytes), "holds a bidirectional control character");  // RLM
  EXPECT_EQ(studentNameProblem("a\u2067b", kMaxStudentIdBytes), "holds a bidirectional control character");  // RLI
  EXPECT_EQ(studentNameProblem("a\xff" "b", kMaxStudentIdBytes), "is not UTF-8 text");
  EXPECT_EQ(studentNameProblem("a\xc3", kMaxStudentIdBytes), "is not UTF-8 text");          // cut short
  EXPECT_EQ(studentNameProblem("\xc0\xaf", kMaxStudentIdBytes), "is not UTF-8 text");      // overlong '/'
  // The config's names are checked as it is read; the message escapes the name.
  EXPECT_EQ(parseLearningConfig("{\"student_name\": \"Ada\u202e\"}", "l.json").message(),
            "l.json: student_name: \"Ada\\u202e\" holds a bidirectional control character");
  EXPECT_FALSE(parseLearningConfig("{\"student\": \"" + std::string(100, 's') + "\"}", "l.json").ok());
  // A malformed LRS URL's credentials stay out of the message.
  EXPECT_EQ(parseLearningConfig(R"({"lrs": "ftp://bob:PW@h/x"})", "l.json").message(),
            "l.json: lrs: \"ftp://***@h/x\" does not start with http:// or https://");
}

TEST(LearningConfig, DefaultPlacesFollowTheEnvironment) {
  ::setenv("DENTSIM_CONFIG", "/etc/lab/learning.json", 1);
  EXPECT_EQ(defaultLearningConfigPath(), "/etc/lab/learning.json");
  ::unsetenv("DENTSIM_CONFIG");
  ::setenv("XDG_CONFIG_HOME", "/cfg", 1);
  EXPECT_EQ(defaultLearningConfigPath(), "/cfg/dentsim/learning.json");
  ::setenv("XDG_DATA_HOME", "/data", 1);
  EXPECT_EQ(defaultOutboxPath(), "/data/dentsim/outbox.jsonl");
  ::unsetenv("XDG_CONFIG_HOME");
  ::unsetenv("XDG_DATA_HOME");
}

}  // namespace
}  // namespace dentsim
