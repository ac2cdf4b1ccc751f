// The checks every command shares: numbers finite and within their physical range, options that cannot apply, outputs that would replace an input, output folders that already hold a recording.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/result.h"
#include "gpu/mesher_kind.h"

namespace dentsim::app {

// A number as users read it: %g, so 1e300 prints as 1e+300 and not as 301 digits.
std::string formatNumber(double value);

// Makes CLI11's parse errors (a refused number, an unknown option) print as every other error of
// dentsim does: one line, "dentsim: --fps: ...", with CLI11's exit code (non-zero). Idempotent; each
// command that adds checked options calls it on the root it is given.
void failInOneLine(CLI::App& root);

// A CLI11 check for a number option: it must parse, be finite (not nan, not inf) and lie in
// [lo, hi]. The message names the range and its unit ("[s]", "[mm]"); the help shows the range.
// One helper for every numeric option, so no command accepts a NaN that a range test lets through
// (NaN compares false with every bound).
CLI::Validator finiteIn(double lo, double hi, const std::string& unit);

// A mesher on the command line (gpu, cpu or auto): gpu/mesher_kind.h's one parser.
CLI::Validator mesherCheck();

// Adds `--mesher gpu|cpu|auto` to a command that meshes the tooth, parsed into `*mesher`.
void addMesherOption(CLI::App& cmd, gpu::MesherKind* mesher);
// Adds what `run` and `demo` draw the tooth with: `--detail-pixels` (screen-sized detail's error,
// 0 for full detail) and `--mesher`.
void addDrawingOptions(CLI::App& cmd, float* detail_pixels, gpu::MesherKind* mesher);

// An option the chosen mode cannot use: the error names the option and why.
// `given` is how often the user gave it (CLI::App::count()).
Status refuseOption(bool given, const std::string& option, const std::string& reason);

// Refuses when any output names the same file as any input (device and inode, so hard and
// symbolic links count too), or lies inside an input that is a folder (a DICOM series: a new file
// there joins the series, a slice's name replaces a slice); empty paths are skipped. The one-line
// message names both paths, escaped.
Status checkOutputsAreNotInputs(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);

// The files a run or a demo writes in its output folder that make it a recording: the session
// (finished or still ".part"), the starting and the final tooth, and a numbered segment's.
bool isRecordingFile(const std::string& file_name);
// The files already in `folder` that a run or a demo writes there (recording files, score report
// and picture, sound, screenshots and frames), for checkOutputsAreNotInputs; none when it is empty.
std::vector<std::string> recordingOutputs(const std::string& folder);
// Refuses an output folder that already holds a recording, unless `overwrite`: a second run would
// replace the first's session and teeth. The message names the folder, one file and --overwrite.
Status checkRecordingFolder(const std::string& folder, bool overwrite);

// Why a file cannot be written at `path`, for a writer whose own error does not say: the folder's
// errno text (missing, "Permission denied", "Read-only file system"), or no space left when the
// file system holds less than `bytes_needed`. Empty when neither shows.
std::string whyCannotWrite(const std::string& path, uint64_t bytes_needed);

// What a tool from the catalog (assets/tools/tools.json) is asked to be.
enum class ToolUse { Bur, Mirror };
// Refuses a name that is not in the tool catalog, or is a tool of another kind ("--bur mirror_size4":
// a mirror is not a bur). The message names the option, the tool and what it is.
Status checkCatalogTool(const std::string& option, const std::string& name, ToolUse use);

}  // namespace dentsim::app
