// Pen path files (CSV or JSON): timed device samples of each pen, which the scripted pen plays and sessions record.
//
// A pen path is what the devices said over time: for each sample, which pen, its grip-frame pose in
// the simulation frame, its buttons and the foot pedal. This header reads and writes it and checks
// it; playing it back (interpolating between samples) belongs to the simulation. docs/PEN_PATHS.md
// describes both encodings.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"

namespace dentsim {

// Which pen a sample belongs to; the file spells it "drill" or "mirror".
enum class PenRole : uint8_t { Drill = 0, Mirror = 1 };

struct PenSample {            // one device reading
  double t_s = 0;             // time since the start [s], >= 0, non-decreasing per pen
  PenRole pen = PenRole::Drill;
  Pose pose;                  // the pen's grip frame in the simulation frame: position [mm], rotation (unit quaternion)
  uint32_t buttons = 0;       // button bits, bit i = button i held
  double pedal = 0;           // foot pedal [0..1]; the drill's turbine speed
  bool operator==(const PenSample&) const = default;  // by value: -0.0 == 0.0
};

// Which frame a path's poses are in. The simulation frame is the grid's; the tooth frame has its
// origin at the occlusal centre, x distal, z the crown axis and y = z x x (docs/PEN_PATHS.md), so a
// script written once fits any tooth whose frame is known. The simulation turns a tooth-frame path
// into the simulation frame before it plays it.
enum class PenFrame : uint8_t { Simulation = 0, Tooth = 1 };

struct PenPath {
  std::vector<PenSample> samples;  // sorted by t_s; samples of one pen keep their file order
  PenFrame frame = PenFrame::Simulation;
  bool operator==(const PenPath&) const = default;
};

// Budget checked while reading, so that a hostile file cannot exhaust memory.
struct PenPathReadLimits {
  uint64_t max_samples = 50'000'000;  // about 4.4 GB of PenSample
};

// Largest file loadPenPath reads [B].
constexpr uint64_t kMaxPenPathFileBytes = uint64_t{512} << 20;

// ---- reading ------------------------------------------------------------------------------------

// Parses the CSV encoding; `where` names the source in errors ("drill.csv"). Errors are one line,
// "<where>:<line>: <problem>" (or "<where>: <problem>" for the whole file). Never throws.
Result<PenPath> parsePenPathCsv(std::string_view text, const std::string& where,
                                const PenPathReadLimits& limits = {});
// Parses the JSON encoding. Errors are one line, "<where>: samples[<i>].<field>: <problem>" for a
// sample, "<where>: <problem>" for the rest. Never throws.
Result<PenPath> parsePenPathJson(std::string_view text, const std::string& where,
                                 const PenPathReadLimits& limits = {});
// Reads a file of at most kMaxPenPathFileBytes: ".csv" or ".json" (any case) picks the encoding, any
// other name is JSON when its first non-blank byte is '{', else CSV. Errors name the path.
Result<PenPath> loadPenPath(const std::string& path, const PenPathReadLimits& limits = {});

// ---- writing ------------------------------------------------------------------------------------

// The CSV text of a path: the header line, then one row per sample, numbers in the shortest form
// that reads back to the same double. The path should pass checkPenPath; a value that does not is
// written as it is (non-finite as "nan"/"inf") and refused when read back.
std::string penPathCsv(const PenPath& path);
// The JSON text of a path, one sample per line; non-finite numbers are written as null.
std::string penPathJson(const PenPath& path);
// Checks the path (checkPenPath), then writes it atomically (temporary file, fsync, rename): JSON
// when `file` ends in ".json" (any case), else CSV.
Status savePenPath(const std::string& file, const PenPath& path);

// ---- details ------------------------------------------------------------------------------------

// "drill" or "mirror" ("unknown" for a value outside the enum).
std::string_view penRoleName(PenRole pen);
// True when the path has at least one sample for `pen`.
bool hasPen(const PenPath& path, PenRole pen);

// Checks what the readers check, without changing anything: at least one sample; finite numbers;
// t_s >= 0 and non-decreasing (the readers sort by time, so a path they return passes); rotation norm
// within kPenRotationNormTolerance of 1; pedal in [0, 1]; a known pen. Errors read
// "<where>: samples[<i>].<field>: <problem>".
Status checkPenPath(const PenPath& path, const std::string& where);

// How far a rotation's norm may be from 1 to be accepted. The readers divide an accepted rotation by
// its norm unless it is already unit to rounding (within 8 ulp of 1), so that reading what was
// written gives back the same bits.
constexpr double kPenRotationNormTolerance = 1e-3;

// The CSV line that declares a path in the tooth frame (before the header; "# frame: simulation" is
// the default and may be written too).
constexpr std::string_view kPenPathCsvToothFrame = "# frame: tooth";

// The CSV header line, without its newline.
constexpr std::string_view kPenPathCsvHeader = "t_s,pen,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,pedal";
// The JSON "format" value and the version this code reads and writes.
constexpr std::string_view kPenPathJsonFormat = "dentsim-pen-path";
constexpr int kPenPathJsonVersion = 1;

}  // namespace dentsim
