// The process-wide budgets: how many bytes one input may occupy once read or inflated, how much memory one command may plan to use, and the flags that set them.
//
// Every reader that allocates from what a file claims (a triangle count, a zstd frame, a NIfTI
// header's dimensions) checks the claim against this budget first, so that a small hostile file
// cannot cost gigabytes. The default keeps any one input, with the copies its reader makes, under
// about 1 GB; `dentsim --max-input-mb N` raises it for real large data. It is set once, before any
// command runs, and only read after that.
#pragma once

#include <cstdint>
#include <string>

namespace dentsim {

inline constexpr uint64_t kDefaultInputBudgetBytes = uint64_t{512} << 20;  // 512 MiB [B]
inline constexpr const char* kInputBudgetFlag = "--max-input-mb";           // the flag that raises it

struct InputBudget {
  uint64_t max_bytes = kDefaultInputBudgetBytes;  // one input's bytes in memory once read or inflated [B]
};

// The budget in force (the default until setInputBudget is called).
InputBudget inputBudget();
// Sets the budget for the whole process (main, from --max-input-mb; tests).
void setInputBudget(const InputBudget& budget);

// "<what> exceeds the limit of <limit> bytes": with " (raise it with --max-input-mb N)" added when
// `limit` is the budget in force, so that every refusal on budget names its flag the same way.
std::string limitExceeded(const std::string& what, uint64_t limit);

// The memory budget: the peak a command may plan for before it allocates (voxelize's plan). By
// default half of the physical memory, and never more than the memory free when asked, so that a
// lab PC running other programs is not driven into swap; `dentsim --max-memory-mb N` sets it.
inline constexpr const char* kMemoryBudgetFlag = "--max-memory-mb";
inline constexpr double kDefaultMemoryShare = 0.5;  // of MemTotal

// The memory on this machine, read from /proc/meminfo: physical (MemTotal) and free now
// (MemAvailable); 0 where it cannot be told.
struct MachineMemory {
  uint64_t total_bytes = 0;
  uint64_t available_bytes = 0;
};
MachineMemory machineMemory();

// The budget in force [B]: the flag's value when given, else the default rule above; 0 when the
// machine's memory cannot be told (nothing is refused then).
uint64_t memoryBudgetBytes();
// Sets the budget for the whole process (main, from --max-memory-mb; tests); 0 restores the default.
void setMemoryBudget(uint64_t bytes);
// How the budget in force was set, for a refusal: "set with --max-memory-mb", or "half of this
// machine's 24 GB, at most its 20 GB free; set it with --max-memory-mb N, in MiB".
std::string memoryBudgetOrigin();

// Bytes as the budgets' messages and the plan show them: "4.3 GB", two significant digits.
std::string gigabytesText(uint64_t bytes);

}  // namespace dentsim
