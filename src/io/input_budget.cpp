// The process-wide input and memory budgets and the one wording of a refusal on each.
#include "io/input_budget.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>

namespace dentsim {
namespace {

// Written once by main before any reader runs; atomic so that a reader on another thread never
// sees a torn value.
std::atomic<uint64_t> g_max_bytes{kDefaultInputBudgetBytes};
std::atomic<uint64_t> g_memory_budget{0};  // 0: the default rule

}  // namespace

InputBudget inputBudget() { return InputBudget{g_max_bytes.load(std::memory_order_relaxed)}; }

void setInputBudget(const InputBudget& budget) { g_max_bytes.store(budget.max_bytes, std::memory_order_relaxed); }

std::string limitExceeded(const std::string& what, uint64_t limit) {
  std::string text = what + " exceeds the limit of " + std::to_string(limit) + " bytes";
  if (limit == inputBudget().max_bytes)
    text += " (the input budget; raise it with " + std::string(kInputBudgetFlag) + " N, in MiB)";
  return text;
}

MachineMemory machineMemory() {
  MachineMemory m;
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  uint64_t kib = 0;
  while (in >> key >> kib >> unit) {
    if (key == "MemTotal:") m.total_bytes = kib * 1024;
    else if (key == "MemAvailable:") m.available_bytes = kib * 1024;
  }
  return m;
}

uint64_t memoryBudgetBytes() {
  if (const uint64_t set = g_memory_budget.load(std::memory_order_relaxed)) return set;
  const MachineMemory m = machineMemory();
  const auto share = uint64_t(double(m.total_bytes) * kDefaultMemoryShare);
  return m.available_bytes > 0 ? std::min(share, m.available_bytes) : share;
}

void setMemoryBudget(uint64_t bytes) { g_memory_budget.store(bytes, std::memory_order_relaxed); }

std::string memoryBudgetOrigin() {
  const std::string flag = std::string(kMemoryBudgetFlag) + " N, in MiB";
  if (g_memory_budget.load(std::memory_order_relaxed)) return "set with " + std::string(kMemoryBudgetFlag);
  const MachineMemory m = machineMemory();
  return "half of this machine's " + gigabytesText(m.total_bytes) + ", at most its " +
         gigabytesText(m.available_bytes) + " free; set it with " + flag;
}

std::string gigabytesText(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g GB", double(bytes) / 1e9);
  return buf;
}

}  // namespace dentsim
