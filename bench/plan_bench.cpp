// Runs `dentsim voxelize` per input path and level as a child and sets its plan beside its peak memory and wall time.
#include "bench/plan_bench.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/host_info.h"
#include "io/atomic_file.h"

namespace dentsim::bench {
namespace fs = std::filesystem;
namespace {

struct ChildRun {
  int exit_code = -1;
  uint64_t peak_bytes = 0;
  double seconds = 0.0;
};

// Runs `argv` with stdout and stderr into `log_path`; the peak is the child's own (ru_maxrss of
// wait4, in KiB on Linux), the time its wall time.
Result<ChildRun> runChild(const std::vector<std::string>& argv, const std::string& log_path) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t child = ::fork();
  if (child < 0) return makeError(argv[0], "cannot start a child process");
  if (child == 0) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  struct rusage usage {};
  while (::wait4(child, &status, 0, &usage) < 0)
    if (errno != EINTR) return makeError(argv[0], "lost its child process");
  ChildRun run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.peak_bytes = uint64_t(usage.ru_maxrss) * 1024;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

// The arguments of `voxelize` for one path, without the level and the output.
Result<std::vector<std::string>> pathArguments(const std::string& path, const PlanBenchSettings& s,
                                               const std::string& scan_dir) {
  const std::string stl = s.data_dir + "/teeth/chai3d_molar_tooth.stl";
  const std::string labels = s.data_dir + "/ct/tooth_2.nii.gz";
  // One tissue: the voxelizer's plan is what is measured, not the layer synthesis after it.
  if (path == "stl-cpu")
    return std::vector<std::string>{"--cpu", "--tooth", stl, "--tooth-material", "dentin", "--scale", "0.04"};
  if (path == "stl-gpu") return std::vector<std::string>{"--tooth", stl, "--tooth-material", "dentin", "--scale", "0.04"};
  if (path == "labels")
    return std::vector<std::string>{"--labels", labels, "--label-map", "1=caries,2=enamel,3=dentin", "--voxel-size", "0.034"};
  if (path == "scan") return std::vector<std::string>{"--dicom", scan_dir};
  return makeError(path, "not a plan benchmark path (stl-cpu, stl-gpu, labels, scan)");
}

// The made scan, once: a DICOM series of tooth_2 with the scanner's blur and noise (make-scan).
Status makeScanOnce(const PlanBenchSettings& s, const std::string& scan_dir) {
  const std::string marker = scan_dir + ".complete";  // beside the series: inside it, it would be listed as a slice
  if (fs::exists(marker)) return Ok{};
  std::error_code ec;
  fs::remove_all(scan_dir, ec);
  Result<ChildRun> made = runChild({s.dentsim, "make-scan", "--labels", s.data_dir + "/ct/tooth_2.nii.gz", "--label-map",
                                    "1=caries,2=enamel,3=dentin", "--voxel-size", "0.034", "-o", scan_dir},
                                   s.scratch + "/make-scan.log");
  if (!made) return made.error();
  if (made->exit_code != 0) return makeError("make-scan", lastLine(s.scratch + "/make-scan.log"));
  return writeFileAtomic(marker, "made by dentsim make-scan\n");
}

}  // namespace

bool PlanRow::memoryWithin() const {
  const double r = memoryRatio();
  return r >= 1.0 / kPlanMemoryTolerance && r <= kPlanMemoryTolerance;
}

bool PlanRow::timeWithin() const {
  const double r = timeRatio();
  return r >= 1.0 / kPlanTimeTolerance && r <= kPlanTimeTolerance;
}

Result<std::vector<PlanRow>> runPlanBench(const PlanBenchSettings& s,
                                          const std::function<void(const std::string&)>& log) {
  std::error_code ec;
  fs::create_directories(s.scratch, ec);
  if (ec) return makeError(s.scratch, "cannot make the scratch folder: " + ec.message());
  for (const char* needed : {"/teeth/chai3d_molar_tooth.stl", "/ct/tooth_2.nii.gz"})
    if (!fs::exists(s.data_dir + needed)) return makeError(s.data_dir + needed, "not found (the shared tooth data)");
  const std::string scan_dir = s.scratch + "/scan";
  std::vector<PlanRow> rows;
  for (const std::string& path : s.paths) {
    Result<std::vector<std::string>> args = pathArguments(path, s, scan_dir);
    if (!args) return args.error();
    if (path == "scan")
      if (Status made = makeScanOnce(s, scan_dir); !made) return made.error();
    for (int level : s.levels) {
      const std::string stem = s.scratch + "/" + path + "-" + std::to_string(level);
      const std::string plan = stem + ".plan.jsonl", out_log = stem + ".log", output = stem + ".dvol";
      fs::remove(plan, ec);
      std::vector<std::string> argv{s.dentsim, "voxelize"};
      argv.insert(argv.end(), args->begin(), args->end());
      for (const std::string& a : {std::string("--level"), std::to_string(level), std::string("--plan-json"), plan,
                                   std::string("-o"), output})
        argv.push_back(a);
      Result<ChildRun> run = runChild(argv, out_log);
      fs::remove(output, ec);
      if (!run) return run.error();
      if (run->exit_code != 0)
        return makeError(path + " level " + std::to_string(level),
                         "voxelize exited " + std::to_string(run->exit_code) + ": " + lastLine(out_log));
      PlanRow row;
      row.path = path;
      row.level = level;
      row.peak_bytes = run->peak_bytes;
      row.seconds = run->seconds;
      std::ifstream in(plan);
      std::string line;
      int stages = 0;
      while (std::getline(in, line)) {
        const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        if (j.is_discarded() || !j.contains("memory_bytes")) return makeError(plan, "not a plan line");
        row.planned_bytes = std::max(row.planned_bytes, j["memory_bytes"].get<uint64_t>());
        row.planned_seconds += j["seconds"].get<double>();
        ++stages;
      }
      if (stages == 0) return makeError(plan, "voxelize wrote no plan");
      if (log) {
        char text[200];
        std::snprintf(text, sizeof text, "%-8s level %2d: planned %.2f GB, %.1f s; took %.2f GB, %.1f s (x%.2f, x%.2f)",
                      path.c_str(), level, double(row.planned_bytes) / 1e9, row.planned_seconds,
                      double(row.peak_bytes) / 1e9, row.seconds, row.memoryRatio(), row.timeRatio());
        log(text);
      }
      rows.push_back(row);
    }
  }
  return rows;
}

nlohmann::json planRowsJson(const std::vector<PlanRow>& rows) {
  nlohmann::json out = {{"benchmark", "plan"},
                        {"cpu", cpuModel()},
                        {"load_average", loadAverage()},
                        {"memory_tolerance", kPlanMemoryTolerance},
                        {"time_tolerance", kPlanTimeTolerance},
                        {"rows", nlohmann::json::array()}};
  for (const PlanRow& r : rows)
    out["rows"].push_back({{"path", r.path},
                           {"level", r.level},
                           {"planned_bytes", r.planned_bytes},
                           {"planned_seconds", r.planned_seconds},
                           {"peak_bytes", r.peak_bytes},
                           {"seconds", r.seconds},
                           {"memory_ratio", r.memoryRatio()},
                           {"time_ratio", r.timeRatio()},
                           {"memory_within", r.memoryWithin()},
                           {"time_within", r.timeWithin()}});
  return out;
}

std::string planRowsTable(const std::vector<PlanRow>& rows) {
  std::ostringstream md;
  md << "| path | level | planned [GB] | peak [GB] | planned / peak | planned [s] | took [s] | planned / took |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  char line[256];
  for (const PlanRow& r : rows) {
    std::snprintf(line, sizeof line, "| %s | %d | %.2f | %.2f | %.2f%s | %.1f | %.1f | %.2f%s |\n", r.path.c_str(), r.level,
                  double(r.planned_bytes) / 1e9, double(r.peak_bytes) / 1e9, r.memoryRatio(),
                  r.memoryWithin() ? "" : " (out)", r.planned_seconds, r.seconds, r.timeRatio(),
                  r.timeWithin() ? "" : " (out)");
    md << line;
  }
  return md.str();
}

Status writePlanReport(const std::string& dir, const std::vector<PlanRow>& rows) {
  for (const auto& [name, text] : {std::pair{std::string("plan.json"), planRowsJson(rows).dump(2) + "\n"},
                                   {std::string("plan.md"), planRowsTable(rows)}})
    if (Status s = writeFileAtomic(dir + "/" + name, text); !s) return s;
  return Ok{};
}

}  // namespace dentsim::bench
