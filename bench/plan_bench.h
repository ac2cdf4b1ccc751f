// The plan benchmark: what `voxelize` estimated it would take (peak memory, time) beside what each run really took.
//
// Each run is a `dentsim voxelize` child process, so that its peak resident memory (wait4's
// ru_maxrss) is its own and not the benchmark's; the estimates come from its --plan-json lines. A
// scan's plan has two stages, the read and the import: the peak compared is the larger estimate,
// the time the sum of both.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace dentsim::bench {

// How far an estimate may stray from what the run took, either way (issue 40's bounds).
inline constexpr double kPlanMemoryTolerance = 1.5;
inline constexpr double kPlanTimeTolerance = 2.0;

// The input paths of `voxelize`, each on a real tooth of the shared data:
//   stl-cpu, stl-gpu  the CHAI3D molar's STL at x0.04 (the CPU reference, the Vulkan voxelizer)
//   labels            the micro-CT labels of tooth_2 (0.034 mm)
//   scan              a DICOM series made from tooth_2 by `make-scan` (read, segmented, imported)
inline const std::vector<std::string>& planBenchPaths() {
  static const std::vector<std::string> paths{"stl-cpu", "stl-gpu", "labels", "scan"};
  return paths;
}

struct PlanRow {
  std::string path;              // one of planBenchPaths()
  int level = 0;
  uint64_t planned_bytes = 0;    // the largest estimate of the plan's stages [B]
  double planned_seconds = 0.0;  // the stages' estimates added [s]
  uint64_t peak_bytes = 0;       // the run's maximum resident memory [B]
  double seconds = 0.0;          // the run's wall time [s]
  double memoryRatio() const { return peak_bytes ? double(planned_bytes) / double(peak_bytes) : 0.0; }
  double timeRatio() const { return seconds > 0 ? planned_seconds / seconds : 0.0; }
  bool memoryWithin() const;     // within kPlanMemoryTolerance either way
  bool timeWithin() const;       // within kPlanTimeTolerance either way
};

struct PlanBenchSettings {
  std::string dentsim;   // the dentsim executable to run
  std::string data_dir;  // the shared real tooth data (teeth/, ct/)
  std::string scratch;   // a folder for the made scan (kept between runs), the plans and the outputs
  std::vector<std::string> paths = planBenchPaths();
  std::vector<int> levels{9, 10, 11, 12};
};

// Runs every path at every level, one child at a time; `log` gets one line per run. Errors: a path
// it does not know, data it cannot find, a run that fails or prints no plan (its last line named).
Result<std::vector<PlanRow>> runPlanBench(const PlanBenchSettings& settings,
                                          const std::function<void(const std::string&)>& log = {});

nlohmann::json planRowsJson(const std::vector<PlanRow>& rows);
std::string planRowsTable(const std::vector<PlanRow>& rows);  // Markdown
// Writes plan.json and plan.md into `dir`, each atomically. Errors name the file.
Status writePlanReport(const std::string& dir, const std::vector<PlanRow>& rows);

}  // namespace dentsim::bench
