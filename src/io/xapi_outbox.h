// The learning records' outbox: xAPI statements as JSON lines, each id once, and the log of those an LRS has taken; both rewritten atomically.
//
// The outbox keeps every statement ever recorded on this PC, one compact JSON object a line, in the
// order they were made; it is what a class report reads. Beside it, "<outbox>.sent" lists the ids
// an LRS has accepted, one a line. Pending = in the outbox, not in the log. Both files are rewritten
// whole (temp file, fsync, rename) under a lock on "<outbox>.lock", so a crash or a second dentsim
// at the same moment never loses a line. docs/LEARNING_RECORDS.md.
#pragma once

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace dentsim {

// "<outbox>.sent".
std::string sentLogPath(const std::string& outbox);

// Every statement in the outbox, in order; none when the file does not exist. Errors name the file
// and line ("outbox.jsonl:3: not a JSON object with a string \"id\"").
Result<std::vector<nlohmann::ordered_json>> readOutbox(const std::string& outbox);
// Adds the statement (an object with a string "id") unless one with its id is there already: true
// when added, false when it was there. Creates the outbox's folder.
Result<bool> appendToOutbox(const std::string& outbox, const nlohmann::ordered_json& statement);

// The ids in the sent log; none when it does not exist.
Result<std::set<std::string>> readSentIds(const std::string& outbox);
// Adds ids to the sent log (each once).
Status markSent(const std::string& outbox, const std::vector<std::string>& ids);
// The statements not yet in the sent log, in the outbox's order.
Result<std::vector<nlohmann::ordered_json>> pendingStatements(const std::string& outbox);

}  // namespace dentsim
