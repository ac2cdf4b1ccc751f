// The learning records' outbox: statements appended in order (earlier bytes never rewritten, a torn line costing only itself), each id once, a sent log that turns them from pending to sent, bad lines named and set aside, the LRS's refusals kept as data, and one sender at a time.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/xapi_outbox.h"
#include "test_support.h"

namespace dentsim {
namespace {

using ojson = nlohmann::ordered_json;

ojson statement(const std::string& id, double raw) { return {{"id", id}, {"result", {{"score", {{"raw", raw}}}}}}; }

std::string readText(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(XapiOutbox, AppendsEachIdOnceInOrderAsJsonLines) {
  test::TempDir dir;
  const std::string outbox = dir.file("records/outbox.jsonl");  // the folder is made on the first append
  EXPECT_TRUE(readOutbox(outbox)->empty());
  EXPECT_TRUE(*appendToOutbox(outbox, statement("a", 1)));
  EXPECT_TRUE(*appendToOutbox(outbox, statement("b", 2)));
  // The same attempt again (even with another score, as a re-scored report would have): not added.
  EXPECT_FALSE(*appendToOutbox(outbox, statement("a", 99)));
  EXPECT_EQ(readText(outbox), R"({"id":"a","result":{"score":{"raw":1.0}}})" "\n" R"({"id":"b","result":{"score":{"raw":2.0}}})" "\n");
  auto all = readOutbox(outbox);
  ASSERT_TRUE(all.ok()) << all.message();
  ASSERT_EQ(all->size(), 2u);
  EXPECT_EQ((*all)[1]["id"], "b");
  // Rewritten by rename: no temporary file is left beside it.
  for (const auto& entry : std::filesystem::directory_iterator(dir.file("records")))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(XapiOutbox, SentLogTurnsPendingIntoSent) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  for (const char* id : {"a", "b", "c"}) ASSERT_TRUE(appendToOutbox(outbox, statement(id, 0)).ok());
  EXPECT_EQ(pendingStatements(outbox)->size(), 3u);
  ASSERT_TRUE(markSent(outbox, {"b"}).ok());
  ASSERT_TRUE(markSent(outbox, {"b", "a"}).ok());  // "b" twice: logged once
  auto pending = pendingStatements(outbox);
  ASSERT_EQ(pending->size(), 1u);
  EXPECT_EQ((*pending)[0]["id"], "c");
  EXPECT_EQ(readText(sentLogPath(outbox)), "b\na\n");
  EXPECT_EQ(readSentIds(outbox)->size(), 2u);
  // The outbox itself keeps every statement, sent or not: the class report reads them all.
  EXPECT_EQ(readOutbox(outbox)->size(), 3u);
}

TEST(XapiOutbox, BadLinesAreNamedByFileAndLine) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  std::ofstream(outbox) << R"({"id":"a"})" "\n" "{not json\n";
  EXPECT_EQ(readOutbox(outbox).message(), outbox + ":2: not valid JSON");
  // Recording passes a bad line over rather than stopping at it; setting it aside is another step.
  std::ofstream(outbox) << R"({"id":"a"})" "\n" R"({"id":3})" "\n";
  EXPECT_TRUE(*appendToOutbox(outbox, statement("c", 0)));
  EXPECT_FALSE(*appendToOutbox(outbox, statement("a", 0)));
  EXPECT_EQ(readText(outbox), R"({"id":"a"})" "\n" R"({"id":3})" "\n" R"({"id":"c","result":{"score":{"raw":0.0}}})" "\n");
}

// Recording and marking sent append: after each of 20 recordings the file holds the earlier bytes
// unchanged, in the same file (a rewrite by rename would give it a new inode).
TEST(XapiOutbox, RecordingAndMarkingSentAppendAndNeverRewriteEarlierBytes) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  std::string before;
  ino_t inode = 0;
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(*appendToOutbox(outbox, statement("s" + std::to_string(i), i)));
    const std::string now = readText(outbox);
    ASSERT_GT(now.size(), before.size());
    EXPECT_EQ(now.substr(0, before.size()), before) << "recording " << i << " changed earlier bytes";
    EXPECT_EQ(now.back(), '\n');
    struct stat st {};
    ASSERT_EQ(::stat(outbox.c_str(), &st), 0);
    if (i > 0) {
      EXPECT_EQ(st.st_ino, inode) << "recording " << i << " replaced the file";
    }
    inode = st.st_ino;
    before = now;
  }
  std::string log;
  for (int i = 0; i < 20; i += 2) {
    ASSERT_TRUE(markSent(outbox, {"s" + std::to_string(i), "s0"}).ok());  // "s0" again: logged once
    const std::string now = readText(sentLogPath(outbox));
    EXPECT_EQ(now.substr(0, log.size()), log);
    log = now;
  }
  EXPECT_EQ(log.substr(0, 9), "s0\ns2\ns4\n");
  EXPECT_EQ(pendingStatements(outbox)->size(), 10u);
  EXPECT_EQ(readOutbox(outbox)->size(), 20u);
}

// A crash mid-write leaves a torn last line (here appended by hand). The next recording ends it
// first, so the torn line is set aside alone and every whole statement before and after it is kept;
// the same for a torn id in the sent log.
TEST(XapiOutbox, ATornLastLineCostsOnlyItself) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  ASSERT_TRUE(*appendToOutbox(outbox, statement("a", 1)));
  ASSERT_TRUE(*appendToOutbox(outbox, statement("b", 2)));
  const std::string whole = readText(outbox);
  std::ofstream(outbox, std::ios::app) << R"({"id":"c","result":{"sco)";
  EXPECT_TRUE(*appendToOutbox(outbox, statement("d", 4)));
  EXPECT_EQ(readText(outbox), whole + R"({"id":"c","result":{"sco)" "\n" R"({"id":"d","result":{"score":{"raw":4.0}}})" "\n");
  auto moved = setAsideBadLines(outbox);
  ASSERT_TRUE(moved.ok()) << moved.message();
  EXPECT_EQ(moved->count, 1u);
  EXPECT_EQ(moved->first, outbox + ":3: not valid JSON");
  auto all = readOutbox(outbox);
  ASSERT_TRUE(all.ok()) << all.message();
  ASSERT_EQ(all->size(), 3u);
  EXPECT_EQ((*all)[0]["id"], "a");
  EXPECT_EQ((*all)[1]["id"], "b");
  EXPECT_EQ((*all)[2]["id"], "d");

  ASSERT_TRUE(markSent(outbox, {"a"}).ok());
  std::ofstream(sentLogPath(outbox), std::ios::app) << "b-torn";
  ASSERT_TRUE(markSent(outbox, {"d"}).ok());
  EXPECT_EQ(readText(sentLogPath(outbox)), "a\nb-torn\nd\n");
  auto pending = pendingStatements(outbox);
  ASSERT_EQ(pending->size(), 1u);
  EXPECT_EQ((*pending)[0]["id"], "b");
}

TEST(XapiOutbox, BadLinesAreSetAsideAndTheGoodOnesKept) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  std::ofstream(outbox) << R"({"id":"a"})" "\n" "{not json\n" R"({"id":"b"})" "\n" R"({"id":3})" "\n";
  auto moved = setAsideBadLines(outbox);
  ASSERT_TRUE(moved.ok()) << moved.message();
  EXPECT_EQ(moved->count, 2u);  // lines 2 and 4
  EXPECT_EQ(moved->first, outbox + ":2: not valid JSON");
  EXPECT_EQ(readText(outbox), R"({"id":"a"})" "\n" R"({"id":"b"})" "\n");
  EXPECT_EQ(readText(badLinesPath(outbox)), "{not json\n" R"({"id":3})" "\n");
  // Recording goes on: the next statement is added after the good ones.
  EXPECT_TRUE(*appendToOutbox(outbox, statement("c", 0)));
  EXPECT_EQ(readOutbox(outbox)->size(), 3u);
  // A clean outbox is left alone, and a later bad line is appended to the side file, never over it.
  EXPECT_EQ(setAsideBadLines(outbox)->count, 0u);
  std::ofstream(outbox, std::ios::app) << "[]\n";
  EXPECT_EQ(setAsideBadLines(outbox)->first, outbox + ":4: not a JSON object with a string \"id\"");
  EXPECT_EQ(readText(badLinesPath(outbox)), "{not json\n" R"({"id":3})" "\n" "[]\n");
  EXPECT_EQ(pendingStatements(outbox)->size(), 3u);
  // No outbox: nothing to do, and nothing made.
  EXPECT_EQ(setAsideBadLines(dir.file("none.jsonl"))->count, 0u);
  EXPECT_FALSE(std::filesystem::exists(badLinesPath(dir.file("none.jsonl"))));
}

TEST(XapiOutbox, OneSenderAtATimeHoldsTheSendersLock) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  {
    OutboxSenderLock first(outbox, true);
    ASSERT_TRUE(first.held()) << first.error();
    // flock conflicts between two opens even in one process: this stands in for a second dentsim.
    OutboxSenderLock second(outbox, false);
    EXPECT_TRUE(second.error().empty()) << second.error();
    EXPECT_FALSE(second.held());
  }
  // Released with its holder (as it is when a sender is killed): the next one gets it.
  OutboxSenderLock next(outbox, false);
  EXPECT_TRUE(next.held());
}

// What an LRS said in refusing a statement is its text, kept byte for byte: a newline, an ESC or a
// printf directive in it stays inside its JSON string, one line a refusal, and the latest per id wins.
TEST(XapiOutbox, RefusalsAreKeptAsDataOneLineEachTheLatestWinning) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  EXPECT_TRUE(readRefusals(outbox)->empty());
  const std::string odd = "line one\nline two %s%n \x1b[2J";
  ASSERT_TRUE(recordRefusal(outbox, "a", Refusal{400, "first"}).ok());
  ASSERT_TRUE(recordRefusal(outbox, "b", Refusal{400, "other"}).ok());
  ASSERT_TRUE(recordRefusal(outbox, "a", Refusal{400, odd}).ok());
  std::ofstream(refusalLogPath(outbox), std::ios::app) << "{\"id\": \"c\", torn";  // a crash mid-write
  const std::string text = readText(refusalLogPath(outbox));
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3);  // three whole lines and the torn one
  auto refusals = readRefusals(outbox);
  ASSERT_TRUE(refusals.ok()) << refusals.message();
  ASSERT_EQ(refusals->size(), 2u);
  EXPECT_EQ(refusals->at("a").reason, odd);
  EXPECT_EQ(refusals->at("a").http_status, 400);
  EXPECT_EQ(refusals->at("b").reason, "other");
}

}  // namespace
}  // namespace dentsim
