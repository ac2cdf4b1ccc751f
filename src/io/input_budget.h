// The process-wide input budget: how many bytes one input may occupy once read or inflated, and the one flag that raises it.
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

}  // namespace dentsim
