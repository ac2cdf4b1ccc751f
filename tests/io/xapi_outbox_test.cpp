// The learning records' outbox: statements kept in order, each id once, a sent log that turns them from pending to sent, bad lines named and set aside, and one sender at a time.
#include <gtest/gtest.h>

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
  std::ofstream(outbox) << R"({"id":"a"})" "\n" R"({"id":3})" "\n";
  EXPECT_EQ(appendToOutbox(outbox, statement("c", 0)).message(), outbox + ":2: not a JSON object with a string \"id\"");
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

}  // namespace
}  // namespace dentsim
