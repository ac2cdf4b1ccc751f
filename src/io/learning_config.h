// The learning records' config file (JSON): who the student is, the course, the school's LRS and its credentials, where the outbox lives.
//
// Found at --config, else $DENTSIM_CONFIG, else $XDG_CONFIG_HOME/dentsim/learning.json (or
// ~/.config/dentsim/learning.json); a missing default file is no error. Every key is optional.
// docs/LEARNING_RECORDS.md shows one.
#pragma once

#include <optional>
#include <string>

#include "core/result.h"

namespace dentsim {

struct LearningConfig {
  std::optional<std::string> student;        // the account name (a student number)
  std::optional<std::string> student_name;   // the display name
  std::optional<std::string> course;         // the course id, a plain name
  std::optional<std::string> lrs;            // the LRS's xAPI endpoint (http or https)
  std::optional<std::string> username;       // HTTP Basic user for the LRS
  std::optional<std::string> password;       // and its password (the file should be readable by its owner only)
  std::optional<std::string> home_page;      // the accounts' homePage IRI
  std::optional<std::string> activity_base;  // the base of the activity IRIs
  std::optional<std::string> language;       // the tasks' language tag ("en-US")
  std::optional<std::string> outbox;         // the outbox file; relative: to the config file's folder
};

// Parses the text. Errors are one line, "<where>: <key>: <problem>": not an object, an unknown key,
// a value that is not a non-empty string, a course that is not a plain name, an LRS or an IRI
// that does not start with http:// or https://.
Result<LearningConfig> parseLearningConfig(const std::string& text, const std::string& where);
// Reads and parses a config file (at most 64 kB); a relative outbox is made relative to the file's folder.
Result<LearningConfig> loadLearningConfig(const std::string& path);

// Why a student's account name (at most 64 bytes) or display name (at most 128 bytes) is refused; empty
// when it is fine. Refused: empty, too long, not UTF-8, control characters (C0, DEL, C1), line and
// paragraph separators, and the bidirectional controls (U+061C, U+200E-F, U+202A-E, U+2066-9), which
// would reorder the text after a name on a report page ("76.1" shown as "1.67").
std::string studentNameProblem(const std::string& name, size_t max_bytes);
constexpr size_t kMaxStudentIdBytes = 64;     // an account name: a student number or a login
constexpr size_t kMaxStudentNameBytes = 128;  // a display name

// $DENTSIM_CONFIG, else $XDG_CONFIG_HOME/dentsim/learning.json, else $HOME/.config/dentsim/learning.json.
std::string defaultLearningConfigPath();
// $XDG_DATA_HOME/dentsim/outbox.jsonl, else $HOME/.local/share/dentsim/outbox.jsonl.
std::string defaultOutboxPath();

}  // namespace dentsim
