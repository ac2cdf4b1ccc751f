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

// $DENTSIM_CONFIG, else $XDG_CONFIG_HOME/dentsim/learning.json, else $HOME/.config/dentsim/learning.json.
std::string defaultLearningConfigPath();
// $XDG_DATA_HOME/dentsim/outbox.jsonl, else $HOME/.local/share/dentsim/outbox.jsonl.
std::string defaultOutboxPath();

}  // namespace dentsim
