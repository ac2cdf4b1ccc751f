// The learning records' outbox: xAPI statements as JSON lines, each id once, and the log of those an LRS has taken; both append-only.
//
// The outbox keeps every statement ever recorded on this PC, one compact JSON object a line, in the
// order they were made; it is what a class report reads. Beside it, "<outbox>.sent" lists the ids
// an LRS has accepted, one a line. Pending = in the outbox, not in the log. Recording a statement and
// marking one sent each append whole lines with one O_APPEND write, fsynced, under a lock on
// "<outbox>.lock": the bytes already there are never rewritten, so a crash mid-write can tear only
// the line being written, never lose an earlier one, and two dentsim at the same moment never lose a
// line. A torn last line is ended before the next line is appended, so it costs only itself. Lines
// that are not statements are moved to "<outbox>.bad", the one time the outbox is rewritten (temp
// file, fsync, rename). A statement the LRS refused as malformed stays pending, and
// "<outbox>.refused" keeps why, as the LRS said it. docs/LEARNING_RECORDS.md.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace dentsim {

// "<outbox>.sent".
std::string sentLogPath(const std::string& outbox);
// "<outbox>.bad": the lines set aside by setAsideBadLines, appended, never read back by dentsim.
std::string badLinesPath(const std::string& outbox);

// What setAsideBadLines moved: nothing when count is 0.
struct SetAsideLines {
  size_t count = 0;   // lines moved to badLinesPath
  std::string first;  // the first one's "<outbox>:<line>: <problem>"
};
// Moves every line that is not a JSON object with a string "id" to badLinesPath (appended, fsynced,
// before the outbox is rewritten without them), so that one damaged line (a hand edit, a disk
// fault) costs only itself and never stops the next attempt being recorded. The caller warns.
Result<SetAsideLines> setAsideBadLines(const std::string& outbox);

// "<outbox>.refused": one JSON line per refusal of a statement by an LRS, appended, never rewritten:
// {"id": the statement's id, "http_status": 400, "reason": what the LRS said}.
std::string refusalLogPath(const std::string& outbox);

// Why an LRS last refused a statement.
struct Refusal {
  long http_status = 0;  // the LRS's answer (400: the statement is malformed)
  std::string reason;    // the LRS's own words (io/lrs_client.h's lrsReason), raw: escape it to show it
};
// Appends a refusal of the statement `id` to the refusal log (fsynced, under the outbox's lock).
Status recordRefusal(const std::string& outbox, const std::string& id, const Refusal& refusal);
// The latest refusal of each statement, by id; none when the log does not exist. Lines that are not
// refusals (a torn write) are passed over: the log only explains, it decides nothing.
Result<std::map<std::string, Refusal>> readRefusals(const std::string& outbox);

// Every statement in the outbox, in order; none when the file does not exist. Errors name the file
// and line ("outbox.jsonl:3: not a JSON object with a string \"id\"").
Result<std::vector<nlohmann::ordered_json>> readOutbox(const std::string& outbox);
// Appends the statement (an object with a string "id") as one line unless one with its id is there
// already: true when added, false when it was there. Lines that are not statements are passed over
// (setAsideBadLines moves them). Creates the outbox's folder.
Result<bool> appendToOutbox(const std::string& outbox, const nlohmann::ordered_json& statement);

// Held by the one process that sends an outbox: an flock on "<outbox>.send.lock" for the object's
// lifetime, so that two senders never post the same statements. Released on close, so a killed
// sender never leaves it held.
class OutboxSenderLock {
 public:
  // wait: block until another sender is done; else held() is false at once while another holds it.
  OutboxSenderLock(const std::string& outbox, bool wait);
  ~OutboxSenderLock();
  OutboxSenderLock(const OutboxSenderLock&) = delete;
  OutboxSenderLock& operator=(const OutboxSenderLock&) = delete;
  bool held() const { return held_; }
  const std::string& error() const { return error_; }  // the lock file could not be opened

 private:
  int fd_ = -1;
  bool held_ = false;
  std::string error_;
};

// The ids in the sent log; none when it does not exist.
Result<std::set<std::string>> readSentIds(const std::string& outbox);
// Appends the ids not yet in the sent log to it (each once); the log is never rewritten.
Status markSent(const std::string& outbox, const std::vector<std::string>& ids);
// The statements not yet in the sent log, in the outbox's order.
Result<std::vector<nlohmann::ordered_json>> pendingStatements(const std::string& outbox);

}  // namespace dentsim
