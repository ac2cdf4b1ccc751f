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
