// The options `run`, `demo` and `replay` spell alike (--out, --overwrite, --shot), defined once, and the old spellings kept as aliases that say they are deprecated.
//
// One definition, so the three commands cannot drift apart in name, meaning, range or help:
//   --out DIR      the folder the command writes into (what it writes there is the command's own)
//   --overwrite    replace a recording already in --out (cli_checks.h, checkRecordingFolder)
//   --shot T       a screenshot when the loop time reaches T seconds, written into --out as
//                  shot-N.png with shot-N.json (N counts the shots in time order; ShotSchedule)
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/result.h"

namespace dentsim::app {

// The latest loop time a shot (or a run's --exit-after) may name: a day of loop time [s].
inline constexpr double kMaxLoopTimeS = 24.0 * 3600.0;

struct OutputOptions {
  std::string out;              // folder for what the command writes; empty: none
  bool overwrite = false;       // replace a recording already in `out`
  std::vector<double> shots_s;  // loop times of screenshots, in the order given [s]
};

// What --out holds for one command, for its help: "the session, the teeth, screenshots and frames".
struct OutputHelp {
  std::string out_holds;
  std::string default_out;  // shown as the default; empty: none
};

// Adds --out, --overwrite and --shot to `cmd`, parsed into `*o` (which must outlive the parse).
void addOutputOptions(CLI::App& cmd, OutputOptions* o, const OutputHelp& help);

// Refuses --shot without a folder to write it into (run and replay have no default --out).
Status checkOutputOptions(const OutputOptions& o, const CLI::App& cmd);

// The one line an old spelling prints on stderr when it is used:
// "dentsim replay: --shot-at is deprecated; use --shot T (--out DIR)".
void warnDeprecated(const std::string& command, const std::string& old_spelling, const std::string& instead);

}  // namespace dentsim::app
