// The command-line checks the commands share (cli_checks.h).
#include "app/cli_checks.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <system_error>

#include <sys/statvfs.h>
#include <unistd.h>

#include "core/text_escape.h"
#include "io/atomic_file.h"
#include "model/tool_generator.h"
#include "render/tooth_lod.h"

namespace dentsim::app {

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void failInOneLine(CLI::App& root) {
  // CLI11 quotes what the user typed; escaped, a value holding a newline or an ESC stays one line.
  root.failure_message(
      [](const CLI::App*, const CLI::Error& e) { return "dentsim: " + escapeControl(e.what(), 2000) + "\n"; });
}

CLI::Validator finiteIn(double lo, double hi, const std::string& unit) {
  const std::string range = "[" + formatNumber(lo) + ", " + formatNumber(hi) + "]" + (unit.empty() ? "" : " " + unit);
  return CLI::Validator(
      [lo, hi, range](std::string& input) -> std::string {
        double value = 0.0;
        // CLI11's own conversion, so that "1e3" and "0x10" read as the option itself reads them.
        if (!CLI::detail::lexical_cast(input, value)) return "\"" + input + "\" is not a number";
        if (!std::isfinite(value)) return "\"" + input + "\" is not a finite number (expected " + range + ")";
        if (value < lo || value > hi) return formatNumber(value) + " is out of range (expected " + range + ")";
        return {};
      },
      "in " + range);
}

Status refuseOption(bool given, const std::string& option, const std::string& reason) {
  if (!given) return Ok{};
  return makeError(option, reason);
}

namespace {

// Whether `out` would be written inside the folder `in` (an input that is a folder: a DICOM series),
// at any depth, following symbolic links on both sides. A series folder read whole takes every
// file in it as a slice, so a new file there changes the input and a slice's name replaces one.
bool liesInsideFolder(const std::string& in, const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(in, ec)) return false;
  const fs::path folder = fs::canonical(in, ec);
  if (ec) return false;
  // The output need not exist yet: its existing part is resolved, the rest taken as written.
  const fs::path target = fs::weakly_canonical(fs::absolute(out, ec), ec);
  if (ec) return false;
  auto f = folder.begin();
  auto t = target.begin();
  for (; f != folder.end(); ++f, ++t)
    if (t == target.end() || *f != *t) return false;
  return t != target.end();  // at least one name below the folder
}

}  // namespace

Status checkOutputsAreNotInputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  for (const std::string& out : outputs) {
    if (out.empty()) continue;
    for (const std::string& in : inputs) {
      if (in.empty()) continue;
      if (sameFile(in, out))
        return makeError(out, "is the same file as the input " + shownPath(in) + "; writing it would destroy the input: "
                              "give another output path");
      if (liesInsideFolder(in, out))
        return makeError(out, "lies inside the input folder " + shownPath(in) + "; writing it would change the input: "
                              "give an output path outside it");
    }
  }
  return Ok{};
}

bool isRecordingFile(const std::string& name) {
  auto ends_with = [&](const std::string& suffix) {
    return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  // session.dses, session-2.dses and their .part files; initial.dvol, initial-2.dvol, final.dvol.
  if (name.rfind("session", 0) == 0 && (ends_with(".dses") || ends_with(".dses.part"))) return true;
  if ((name.rfind("initial", 0) == 0 || name.rfind("final", 0) == 0) && ends_with(".dvol")) return true;
  return false;
}

std::vector<std::string> recordingOutputs(const std::string& folder) {
  namespace fs = std::filesystem;
  std::vector<std::string> found;
  std::error_code ec;
  if (folder.empty() || !fs::is_directory(folder, ec)) return found;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const bool picture = (name.rfind("shot-", 0) == 0 || name.rfind("frame-", 0) == 0);
    if (isRecordingFile(name) || picture || name.rfind("score", 0) == 0 || name == "sound.wav" || name == "final.ply")
      found.push_back(it->path().string());
  }
  return found;
}

Status checkRecordingFolder(const std::string& folder, bool overwrite) {
  namespace fs = std::filesystem;
  if (overwrite) return Ok{};
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return Ok{};  // a new folder, or not a folder (the run names that)
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (isRecordingFile(name))
      return makeError(folder, "already holds a recording (" + shownPath(name) +
                                   "); a new run would replace it: give another --out folder, or --overwrite to replace it");
  }
  return Ok{};
}

std::string whyCannotWrite(const std::string& path, uint64_t bytes_needed) {
  namespace fs = std::filesystem;
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (::access(folder.c_str(), W_OK) != 0) return shownPath(folder.string()) + ": " + std::strerror(errno);
  struct statvfs fs_info {};
  if (::statvfs(folder.c_str(), &fs_info) == 0) {
    const uint64_t free_bytes = uint64_t(fs_info.f_bavail) * uint64_t(fs_info.f_frsize);
    if (free_bytes < bytes_needed)
      return shownPath(folder.string()) + ": " + std::strerror(ENOSPC) + " (" + std::to_string(free_bytes) + " bytes free, up to " +
             std::to_string(bytes_needed) + " needed)";
  }
  return {};
}

Status checkCatalogTool(const std::string& option, const std::string& name, ToolUse use) {
  const bool bur = use == ToolUse::Bur;
  const char* wanted = bur ? "a bur" : "a mirror";
  std::string names;
  for (const ToolSpec& s : toolCatalog()) {
    const bool is_bur = isBur(s.kind);
    if (bur ? is_bur : s.kind == ToolKind::Mirror) names += (names.empty() ? "" : ", ") + std::string(s.name);
  }
  for (const ToolSpec& s : toolCatalog()) {
    if (name != s.name) continue;
    const bool is_bur = isBur(s.kind);
    if (bur ? is_bur : s.kind == ToolKind::Mirror) return Ok{};
    return makeError(option, "\"" + escapeControl(name) + "\" is a " + toolKindName(s.kind) + ", not " + wanted + " (" +
                                 wanted + " is one of " + names + ")");
  }
  return makeError(option, "\"" + escapeControl(name) + "\" is not in the tool catalog (" + wanted + " is one of " + names + ")");
}

CLI::Validator mesherCheck() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return gpu::parseMesherKind(text) ? std::string()
                                          : "\"" + text + "\" is not a mesher (" + gpu::kMesherKindChoices + ")";
      },
      gpu::kMesherKindChoices, "mesher");
}

void addDrawingOptions(CLI::App& cmd, float* detail_pixels, gpu::MesherKind* mesher) {
  cmd.add_option("--detail-pixels", *detail_pixels,
                 "Draw each part of the tooth from the coarsest copy within this many pixels of error; 0: full "
                 "detail everywhere")
      ->check(finiteIn(0.0, render::kMaxDetailPixels, "px"))
      ->capture_default_str();
  addMesherOption(cmd, mesher);
}

void addMesherOption(CLI::App& cmd, gpu::MesherKind* mesher) {
  cmd.add_option_function<std::string>(
         "--mesher", [mesher](const std::string& text) { *mesher = *gpu::parseMesherKind(text); },
         "Who meshes the tooth: the GPU's compute kernel, CPU threads, or auto (CPU threads where the Vulkan "
         "device is itself a CPU, as lavapipe is)")
      ->check(mesherCheck())
      ->default_str("auto");
}

}  // namespace dentsim::app
