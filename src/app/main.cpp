// dentsim's command-line entry: parses the subcommand, runs it, and turns any escape into a one-line error.
#include <cstdarg>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/data_folder.h"
#include "core/text_escape.h"
#include "io/input_budget.h"

namespace dentsim::app {

// Both end every message the same way: whatever outside text it quotes (a picture's name from an
// outbox, a tool named in a session) has its control bytes escaped here, once for every caller, so
// a message stays one line and cannot drive the terminal. Escaping is idempotent: text a reader
// escaped already reads the same.
int fail(const std::string& message) {
  std::cerr << "dentsim: " << escapeControl(message, message.size()) << "\n";
  return 1;
}

void warn(const std::string& message) {
  std::cerr << "dentsim: warning: " << escapeControl(message, message.size()) << "\n";
}

void warnf(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string message(n > 0 ? size_t(n) : 0, '\0');
  if (n > 0) std::vsnprintf(message.data(), message.size() + 1, format, again);
  va_end(again);
  warn(message);
}

}  // namespace dentsim::app

int main(int argc, char** argv) {
  using namespace dentsim::app;
  CLI::App root{"dentsim: dental surgery simulator (voxel tooth, haptic drilling, automatic scoring)"};
  root.require_subcommand(1);
  // The version and the data folder this binary found, which says where an installed copy reads from.
  root.set_version_flag("--version", versionText(executableFolder()));
  failInOneLine(root);  // a rejected option or number is one "dentsim: ..." line, as every other error
  // One budget for every input a command reads (io/input_budget.h); raised for real large data.
  uint64_t max_input_mb = dentsim::kDefaultInputBudgetBytes >> 20;
  root.add_option(dentsim::kInputBudgetFlag, max_input_mb,
                  "Most memory one input may take once read or decompressed [MiB] (default " +
                      std::to_string(max_input_mb) + "); raise it for real large data")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 20));
  // One budget for the memory a command plans to use at its peak (io/input_budget.h).
  uint64_t max_memory_mb = 0;
  root.add_option(dentsim::kMemoryBudgetFlag, max_memory_mb,
                  "Most memory a command may plan to use at its peak [MiB] (default: half of this machine's "
                  "memory, at most what is free); a job planned beyond it is refused before it allocates")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 24));
  Action action;
  addGpuCommand(root, action);
  addVoxelizeCommand(root, action);
  addInfoCommand(root, action);
  addExportCommand(root, action);
  addBenchCommand(root, action);
  addMakeToothCommand(root, action);
  addMakeScanCommand(root, action);
  addMeshCommand(root, action);
  addRunCommand(root, action);
  addDevicesCommand(root, action);
  addOutboxCommand(root, action);
  addDemoCommand(root, action);
  addReplayCommand(root, action);
  addScoreCommand(root, action);
  addTaskCommand(root, action);
  addTaskValidateCommand(*root.get_subcommand("task"), action);
  addReportCommand(root, action);
  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return root.exit(e);
  }
  dentsim::setInputBudget({max_input_mb << 20});
  dentsim::setMemoryBudget(max_memory_mb << 20);
  // Errors the environment can cause come back as Result; these catches only keep a bug or an
  // exhausted memory from ending in an abort without a message.
  try {
    return action ? action() : fail("no command given");
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what());
  }
}
