// The session file (.dses): every haptic step's device readings, written while the session runs, so that it replays exactly.
//
// Layout (little-endian): the 8-byte magic "DSESSION", a u32 format version, a u32 header length,
// the header (UTF-8 JSON, SessionInfo), the header's XXH64 (u64); then records until the end of the
// file. A record is a u8 kind, three zero bytes, a u32 payload length, the payload and the XXH32
// of kind, zero bytes, length and payload (u32). Records checksum one by one, so a file cut off
// anywhere still reads up to its last whole record, and the writer can flush as often as it likes.
// docs/SESSIONS.md gives every field.
//
// io reads and writes the records and checks what a file alone can show (checksums, ranges,
// step order); what the readings mean (the loop, the tools, the parameter set's JSON) is sim's.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"

namespace dentsim {

inline constexpr uint32_t kSessionFileVersion = 1;

// What the session is about; the header of the file.
struct SessionInfo {
  std::string created_utc;      // ISO 8601 ("2026-11-22T10:21:44Z") when recording started
  std::string program;          // "dentsim 0.1.0" (who wrote it)
  double rate_hz = 1000.0;      // haptic loop rate: step k ran at loop time k / rate_hz [s]
  std::string task;             // task name ("caries_removal"), empty for free drilling
  std::string tooth_hash;       // volumeHash() of the starting tooth, 16 lower-case hex digits
  std::string tooth_file;       // the starting volume, relative to the session file's folder; may be empty
  std::string tooth_source;     // how the tooth was made ("built-in molar, level 9, CPU voxelizer")
  int tooth_level = 0;          // octree level of the tooth's grid
  double voxel_mm = 0.0;        // voxel edge [mm]
  std::string drill_tool;       // tool on the drill pen ("round_bur_010"); never empty
  std::string mirror_tool;      // tool on the mirror pen; empty when none
  std::string params_json;      // the parameter set at step 0 (simParamsJson text); sim parses it
  std::string guide_json;       // the guide's spring and path the drill was pulled along (sim/guide_spring.h's
                                // JSON object); empty: the session was not guided, and the header has no "guide"
};

// The current time as ISO 8601 UTC ("2026-11-22T10:21:44Z"), as SessionInfo::created_utc holds it.
std::string utcNow();

// One pen's reading as the loop consumed it.
struct SessionPenReading {
  Pose grip;                    // grip frame in the simulation frame [mm]
  Vec3 velocity;                // of the grip point [mm/s]
  Vec3 angular_velocity;        // [rad/s]
  uint32_t buttons = 0;
  double pedal = 0.0;           // [0, 1]
};

// What a budgeted haptic step reached (sim/haptic_loop.h): replay follows it, not the clock.
// The default (kAll everywhere) is a step that did all its work; only other steps write a record.
struct SessionSchedule {
  static constexpr uint32_t kAll = 0xFFFFFFFFu;
  std::array<uint32_t, 2> clusters{kAll, kAll};  // clusters each pen's contact pass reached (PenRole order)
  uint32_t cuts = kAll;                          // queued cut jobs run at the end of the step; kAll: every one
  bool isDefault() const { return clusters[0] == kAll && clusters[1] == kAll && cuts == kAll; }
  bool operator==(const SessionSchedule&) const = default;
};

// One haptic step: what went in (readings) and, for review and scoring, what came out.
struct SessionStep {
  uint64_t step = 0;            // loop step index; steps follow one another (k, k+1, ...)
  int64_t wall_ns = 0;          // steady clock when the step ran, from the session's start [ns]
  uint32_t params_serial = 0;   // the parameter set in force (0: the header's; see SessionParams)
  uint8_t pens = 0;             // bit r set: pen r (PenRole: drill 0, mirror 1) gave a reading
  std::array<SessionPenReading, 2> reading{};  // valid where the pen's bit is set
  std::array<Vec3, 2> force_n{};               // force each pen was told to render [N]
  std::array<uint32_t, 2> contacts{};          // shell points of each tool inside tissue
  bool hasReading(size_t pen) const { return (pens >> pen) & 1u; }
  SessionSchedule schedule;                    // what the step reached; unless default, a schedule record follows the step's
};

// A parameter set that came into force during the session (a teacher's change).
struct SessionParams {
  uint32_t serial = 0;          // 1, 2, ... in the order they came into force
  uint64_t from_step = 0;       // the first step that used it
  std::string params_json;
};

// Steps the recorder could not keep (its queue overflowed): the file cannot replay past them.
struct SessionGap {
  uint64_t first_step = 0;
  uint64_t steps = 0;
};

// A pen's device changing state during the session: a fault, an unplug, its return. Recorded so
// that a review says which pen failed and when; replay does not use it (the steps already hold
// what the loop read).
struct SessionDeviceEvent {
  uint64_t step = 0;            // the first step run after the change was seen
  uint8_t pen = 0;              // PenRole: drill 0, mirror 1
  std::string state;            // the device's new state ("fault", "disconnected", "ready", ...)
  std::string reason;           // its reason, printable ASCII, at most 200 bytes
};

// How the session ended, when it ended cleanly.
struct SessionEnd {
  uint64_t steps = 0;           // steps run
  std::string final_hash;       // volumeHash() of the tooth after the last step
  std::string reason;           // "completed", "stopped", ...
};

struct SessionRecording {
  SessionInfo info;
  std::vector<SessionStep> steps;
  std::vector<SessionParams> params;  // by serial, serial 1 first
  std::vector<SessionGap> gaps;
  std::vector<SessionDeviceEvent> devices;  // in step order
  std::optional<SessionEnd> end;      // absent: the recording stopped without its end record
  // Set when the file ends inside a record (a crash mid-write): what was read is kept, and this
  // says what was dropped ("session.dses: cut off at byte 123456 inside record 789; read 788 steps").
  std::string truncation_warning;
};

struct SessionReadLimits {
  uint64_t max_bytes = uint64_t{16} << 30;      // refuse files larger than this
  uint64_t max_steps = 200'000'000;             // about 55 hours at 1 kHz
  uint64_t max_device_events = 100'000;         // pen state changes; a real session has a handful
  uint32_t max_header_bytes = 16u << 20;
  uint32_t max_record_bytes = 16u << 20;
};

// Reads and checks a whole session. A file that is not a session, a checksum that fails in the
// middle of the file, a value out of range or steps out of order are errors: one line naming the
// file, the record (its index and byte offset) and the problem. A file cut off inside its last
// record is not an error: see truncation_warning. Never throws.
Result<SessionRecording> readSessionFile(const std::string& path, const SessionReadLimits& limits = {});
// The same on bytes in memory (the fuzz tests call this); `where` names the source.
Result<SessionRecording> parseSession(std::span<const uint8_t> bytes, const std::string& where,
                                      const SessionReadLimits& limits = {});

// Writes a session as it runs. Records are buffered in memory until flush(); flush() hands them to
// the kernel (a crash of dentsim then loses nothing flushed) and sync() to the disk. The file is
// written under `path + ".part"` and renamed to `path` by finish(), so an existing file at `path`
// survives until the new session is complete, and a crash leaves a readable ".part" file.
// Not thread-safe: one recorder thread owns it.
class SessionWriter {
 public:
  SessionWriter() = default;
  ~SessionWriter();  // closes without finishing: the ".part" file stays
  SessionWriter(const SessionWriter&) = delete;
  SessionWriter& operator=(const SessionWriter&) = delete;

  // Creates `path`.part and writes the header. Errors name the path.
  Status open(const std::string& path, const SessionInfo& info);
  void add(const SessionStep& step);  // and, unless step.schedule is the default, its schedule record
  void add(const SessionParams& params);
  void add(const SessionGap& gap);
  void add(const SessionDeviceEvent& event);
  Status flush();
  Status sync();
  // Writes the end record, flushes, syncs, closes and renames the file to its final name.
  Status finish(const SessionEnd& end);
  bool isOpen() const { return file_ != nullptr; }
  const std::string& partPath() const { return part_path_; }
  uint64_t bytesWritten() const { return bytes_written_; }

 private:
  void addRecord(uint8_t kind, const std::vector<uint8_t>& payload);
  std::FILE* file_ = nullptr;
  std::string path_, part_path_;
  std::vector<uint8_t> buffer_;
  std::vector<uint8_t> scratch_;
  uint64_t bytes_written_ = 0;
  std::string error_;  // the first failed write: later records are dropped and flush() repeats it
};

// The whole session in memory to bytes (what a SessionWriter writes for the same calls, in order:
// header, params records in serial order merged with the steps by from_step, each step's schedule
// record right after it, gaps, end).
std::vector<uint8_t> encodeSession(const SessionRecording& recording);

}  // namespace dentsim
