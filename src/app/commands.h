// Registration of dentsim's subcommands: each cmd_*.cpp adds one subcommand and the action it runs.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace dentsim::app {

// What main() runs after parsing: returns the process exit code (0 success, 1 failure).
using Action = std::function<int()>;

// Each adds its subcommand to `root`. When the user picks it, the subcommand's parse callback sets
// `action` to run it with the parsed options.
void addGpuCommand(CLI::App& root, Action& action);
void addVoxelizeCommand(CLI::App& root, Action& action);
void addInfoCommand(CLI::App& root, Action& action);
void addExportCommand(CLI::App& root, Action& action);
void addBenchCommand(CLI::App& root, Action& action);
void addMakeToothCommand(CLI::App& root, Action& action);
void addMakeScanCommand(CLI::App& root, Action& action);
void addMeshCommand(CLI::App& root, Action& action);
void addDemoCommand(CLI::App& root, Action& action);
void addReplayCommand(CLI::App& root, Action& action);
void addScoreCommand(CLI::App& root, Action& action);
void addTaskCommand(CLI::App& root, Action& action);
// `dentsim task validate`, added under `task` by main once addTaskCommand has made it.
void addTaskValidateCommand(CLI::App& task_cmd, Action& action);
void addRunCommand(CLI::App& root, Action& action);
void addDevicesCommand(CLI::App& root, Action& action);
// `dentsim report` (app/cmd_report.cpp).
void addReportCommand(CLI::App& root, Action& action);
// `dentsim outbox send|status` (app/learning_cli.cpp).
void addOutboxCommand(CLI::App& root, Action& action);
// `dentsim bench scores`, added under `bench` by addBenchCommand.
void addScoresBenchCommand(CLI::App& bench, Action& action);

// Prints "dentsim: <message>" on stderr and returns exit code 1: the one way commands report errors.
int fail(const std::string& message);
// Prints "dentsim: warning: <message>" on stderr and goes on: the one way commands warn. The message
// is data (escape a name from outside before it goes in), never a format.
void warn(const std::string& message);
// warn() with printf formatting, for warnings that show numbers. The format is a literal at every
// call site; text from a file or the user goes in as a "%s" argument.
void warnf(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace dentsim::app
