// The options run, demo and replay share (shared_options.h).
#include "app/shared_options.h"

#include <cstdio>

#include "app/cli_checks.h"

namespace dentsim::app {

void addOutputOptions(CLI::App& cmd, OutputOptions* o, const OutputHelp& help) {
  if (!help.default_out.empty()) o->out = help.default_out;
  CLI::Option* out = cmd.add_option("--out", o->out,
                                    "Folder for " + help.out_holds + "; one that already holds a recording needs --overwrite");
  if (!help.default_out.empty()) out->capture_default_str();
  cmd.add_flag("--overwrite", o->overwrite, "Write into an --out folder that already holds a recording, replacing its files");
  cmd.add_option("--shot", o->shots_s,
                 "Loop time of a screenshot, written into --out as shot-N.png with shot-N.json [s]; repeatable")
      ->check(finiteIn(0.0, kMaxLoopTimeS, "s"));
}

Status checkOutputOptions(const OutputOptions& o, const CLI::App& cmd) {
  return refuseOption(cmd.count("--shot") > 0 && o.out.empty(), "--shot",
                      "writes shot-N.png into the --out folder; give --out DIR");
}

void warnDeprecated(const std::string& command, const std::string& old_spelling, const std::string& instead) {
  std::fprintf(stderr, "dentsim %s: %s is deprecated; use %s\n", command.c_str(), old_spelling.c_str(), instead.c_str());
}

}  // namespace dentsim::app
