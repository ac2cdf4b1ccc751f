// Tests of src/eval/student_records.cpp: one student's attempts read from hand-made outbox files, counted by hand.
#include "eval/student_records.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "eval/learning_record.h"
#include "io/learning_config.h"
#include "test_support.h"

namespace dentsim {
namespace {

const std::string kBase = "https://school.example/xapi";

// One statement line as the outbox keeps it: the student's account, the task's activity, a raw
// score, a time, and (when given) the undercut part's points out of 50.
std::string line(const std::string& id, const std::string& student, const std::string& course, const std::string& task,
                 double score, const std::string& time, double undercut = -1) {
  std::string parts;
  if (undercut >= 0)
    parts = R"(,"extensions":{"https://dentsim.invalid/xapi/extensions/parts":{"components":{"undercut":{"points":)" +
            std::to_string(undercut) + R"(,"max":50}},"deductions":{}}})";
  return R"({"id":")" + id + R"(","actor":{"objectType":"Agent","account":{"homePage":"https://dentsim.invalid","name":")" +
         student + R"("}},"verb":{"id":"http://adlnet.gov/expapi/verbs/completed"},"object":{"objectType":"Activity","id":")" +
         taskActivityIri(kBase, course, task) + R"("},"result":{"score":{"raw":)" + std::to_string(score) + R"(})" + parts +
         R"(},"timestamp":")" + time + R"("})";
}

TEST(StudentRecords, CountsBestAndTheLastThreeOfOneStudentAtOneTask) {
  // s1 tried class1 four times (60, 82, 75, 90: written out of time order), class2 once; s2 once.
  const std::string text = line("a", "s1", "c", "class1", 82, "2026-11-27T09:00:00Z", 40) + "\n" +
                           line("b", "s1", "c", "class1", 60, "2026-11-27T08:00:00Z", 30) + "\n" +
                           line("c", "s2", "c", "class1", 99, "2026-11-27T08:30:00Z") + "\n" +
                           line("d", "s1", "c", "class2", 55, "2026-11-27T08:45:00Z") + "\n" +
                           "\n" +  // a blank line is allowed
                           line("e", "s1", "c", "class1", 75, "2026-11-27T10:00:00Z", 45) + "\n" +
                           line("f", "s1", "c", "class1", 90, "2026-11-27T11:00:00Z", 48) + "\n";
  const StudentRecords r = parseStudentRecords(text, "outbox.jsonl", "s1");
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_EQ(r.by_activity.size(), 2u);  // class1 and class2; s2's line is not s1's

  const TaskRecord one = taskRecord(r, taskActivityIri(kBase, "c", "class1"));
  EXPECT_EQ(one.attempts, 4);
  ASSERT_TRUE(one.best);
  EXPECT_DOUBLE_EQ(*one.best, 90.0);  // not s2's 99
  // The last three by time, oldest first: 82 (09:00), 75 (10:00), 90 (11:00); 60 (08:00) is older.
  ASSERT_EQ(one.recent.size(), 3u);
  EXPECT_DOUBLE_EQ(one.recent[0].score, 82.0);
  EXPECT_DOUBLE_EQ(one.recent[1].score, 75.0);
  EXPECT_DOUBLE_EQ(one.recent[2].score, 90.0);
  // Their parts come along: the undercut's points out of 50.
  ASSERT_EQ(one.recent[2].parts.size(), 1u);
  EXPECT_EQ(one.recent[2].parts[0].name, "undercut");
  EXPECT_DOUBLE_EQ(*one.recent[2].parts[0].points, 48.0);
  EXPECT_EQ(one.recent[2].source, "outbox.jsonl:7");  // the outbox's own line number

  const TaskRecord two = taskRecord(r, taskActivityIri(kBase, "c", "class2"));
  EXPECT_EQ(two.attempts, 1);
  EXPECT_DOUBLE_EQ(*two.best, 55.0);
  // A task never tried: no attempts, no best.
  const TaskRecord none = taskRecord(r, taskActivityIri(kBase, "c", "class5"));
  EXPECT_EQ(none.attempts, 0);
  EXPECT_FALSE(none.best);
  EXPECT_TRUE(none.recent.empty());
}

TEST(StudentRecords, TheSameTaskInAnotherCourseIsAnotherTask) {
  const std::string text = line("a", "s1", "cons-101", "class1", 70, "2026-11-27T08:00:00Z") + "\n" +
                           line("b", "s1", "cons-102", "class1", 40, "2026-11-27T09:00:00Z") + "\n";
  const StudentRecords r = parseStudentRecords(text, "o", "s1");
  EXPECT_EQ(taskRecord(r, taskActivityIri(kBase, "cons-101", "class1")).attempts, 1);
  EXPECT_DOUBLE_EQ(*taskRecord(r, taskActivityIri(kBase, "cons-102", "class1")).best, 40.0);
}

TEST(StudentRecords, PassedAgainstTheTasksMarkAndNeverWithoutOne) {
  TaskRecord r;
  EXPECT_FALSE(taskPassed(r, 60.0));  // no attempts
  r.attempts = 2;
  r.best = 59.9;
  EXPECT_FALSE(taskPassed(r, 60.0));
  r.best = 60.0;
  EXPECT_TRUE(taskPassed(r, 60.0));  // the mark itself passes, as the statement's verb says
  EXPECT_FALSE(taskPassed(r, std::nullopt));
}

TEST(StudentRecords, ADamagedLineCostsOnlyItselfAndOthersDamagedLinesAreNotThisStudents) {
  const std::string text = line("a", "s1", "c", "t", 70, "2026-11-27T08:00:00Z") + "\n" +
                           "{\"id\":\"torn" + "\n" +  // a torn write: nobody's
                           // this student's, but its score is out of range
                           R"({"id":"x","actor":{"account":{"name":"s1"}},"verb":{"id":"v/completed"},"object":{"id":")" +
                           taskActivityIri(kBase, "c", "t") + R"("},"result":{"score":{"raw":400}}})" + "\n" +
                           // a statement with no score (launched): no attempt, no warning
                           R"({"id":"y","actor":{"account":{"name":"s1"}},"verb":{"id":"v/launched"},"object":{"id":")" +
                           taskActivityIri(kBase, "c", "t") + R"("}})" + "\n" +
                           line("b", "s1", "c", "t", 80, "2026-11-27T09:00:00Z") + "\n";
  const StudentRecords r = parseStudentRecords(text, "o.jsonl", "s1");
  const TaskRecord t = taskRecord(r, taskActivityIri(kBase, "c", "t"));
  EXPECT_EQ(t.attempts, 2);
  EXPECT_DOUBLE_EQ(*t.best, 80.0);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("o.jsonl:3"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("raw"), std::string::npos) << r.warnings[0];
}

TEST(StudentRecords, AMissingOutboxOrNoStudentIsNoAttempts) {
  test::TempDir dir;
  auto none = readStudentRecords(dir.file("outbox.jsonl"), "s1");
  ASSERT_TRUE(none) << none.message();
  EXPECT_TRUE(none->by_activity.empty());
  std::ofstream(dir.file("outbox.jsonl")) << line("a", "s1", "c", "t", 70, "2026-11-27T08:00:00Z") << "\n";
  auto one = readStudentRecords(dir.file("outbox.jsonl"), "s1");
  ASSERT_TRUE(one) << one.message();
  EXPECT_EQ(taskRecord(*one, taskActivityIri(kBase, "c", "t")).attempts, 1);
  auto nobody = readStudentRecords(dir.file("outbox.jsonl"), "");
  ASSERT_TRUE(nobody);
  EXPECT_TRUE(nobody->by_activity.empty());
}

}  // namespace
}  // namespace dentsim

namespace dentsim {
namespace {

TEST(StudentName, KeptInTheConfigBesideItsOtherKeysAndReadBack) {
  test::TempDir dir;
  // No file yet: made, with its folder.
  const std::string fresh = dir.file("cfg/dentsim/learning.json");
  ASSERT_TRUE(keepStudentName(fresh, "s1001"));
  auto read = loadLearningConfig(fresh);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(read->student.value_or(""), "s1001");
  // A file with the school's keys: they stay.
  const std::string school = dir.file("school.json");
  std::ofstream(school) << R"({"course":"cons-101","lrs":"https://lrs.example/xapi"})";
  ASSERT_TRUE(keepStudentName(school, "s2002"));
  read = loadLearningConfig(school);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(read->student.value_or(""), "s2002");
  EXPECT_EQ(read->course.value_or(""), "cons-101");
  EXPECT_EQ(read->lrs.value_or(""), "https://lrs.example/xapi");
}

TEST(StudentName, ABadNameOrABrokenConfigIsRefusedAndTheFileKept) {
  test::TempDir dir;
  const std::string path = dir.file("learning.json");
  EXPECT_FALSE(keepStudentName(path, ""));
  EXPECT_FALSE(keepStudentName(path, "a\nb"));
  EXPECT_FALSE(std::filesystem::exists(path));
  std::ofstream(path) << "{\"course\": ";  // a hand edit gone wrong
  const Status st = keepStudentName(path, "s1");
  ASSERT_FALSE(st);
  EXPECT_NE(st.message().find("learning.json"), std::string::npos) << st.message();
  std::ifstream in(path);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "{\"course\": ");
}

}  // namespace
}  // namespace dentsim
