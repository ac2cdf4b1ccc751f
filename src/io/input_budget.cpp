// The process-wide input budget and the one wording of a refusal on it.
#include "io/input_budget.h"

#include <atomic>

namespace dentsim {
namespace {

// Written once by main before any reader runs; atomic so that a reader on another thread never
// sees a torn value.
std::atomic<uint64_t> g_max_bytes{kDefaultInputBudgetBytes};

}  // namespace

InputBudget inputBudget() { return InputBudget{g_max_bytes.load(std::memory_order_relaxed)}; }

void setInputBudget(const InputBudget& budget) { g_max_bytes.store(budget.max_bytes, std::memory_order_relaxed); }

std::string limitExceeded(const std::string& what, uint64_t limit) {
  std::string text = what + " exceeds the limit of " + std::to_string(limit) + " bytes";
  if (limit == inputBudget().max_bytes)
    text += " (the input budget; raise it with " + std::string(kInputBudgetFlag) + " N, in MiB)";
  return text;
}

}  // namespace dentsim
