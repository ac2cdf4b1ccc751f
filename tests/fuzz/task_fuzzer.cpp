// libFuzzer entry for the task parser: any input either fails with one line naming the source or gives a task that keeps the schema's rules.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "eval/task.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const dentsim::Result<dentsim::Task> task = dentsim::parseTask(text, "fuzz.json");
  if (!task.ok()) {
    const std::string& m = task.message();
    if (m.rfind("fuzz.json: ", 0) != 0 || m.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  if (!(task->target_s > 0) || !std::isfinite(task->target_s) || !(task->force_error_n > 0)) std::abort();
  if (task->kind == dentsim::TaskKind::Caries && !(task->failure_s > task->target_s)) std::abort();
  return 0;
}
