// Session headers shared by the io, sim, eval, device and CLI tests: one place for who wrote a test session and when.
#pragma once

#include <string>

#include "io/session_file.h"

namespace dentsim::test {

// A session header with only its writer and start time set: a fixed time, so that two recordings of
// the same run are equal byte for byte. sessionHeader, recordScriptedSession or the test adds the rest.
inline SessionInfo sessionInfo(const std::string& created_utc) {
  SessionInfo info;
  info.created_utc = created_utc;
  info.program = "dentsim test";
  return info;
}

// The header of a recording made step by step, with no loop behind it: the starting tooth's hash,
// level and voxel edge [mm], the drill, and an empty parameter set.
inline SessionInfo handMadeSessionInfo(const std::string& tooth_hash, int tooth_level, double voxel_mm,
                                       const std::string& drill_tool) {
  SessionInfo info = sessionInfo("2026-01-05T09:00:00Z");
  info.tooth_hash = tooth_hash;
  info.tooth_level = tooth_level;
  info.voxel_mm = voxel_mm;
  info.drill_tool = drill_tool;
  info.params_json = "{}\n";
  return info;
}

// A header with every field but the guide set, as dentsim 0.1.0 writes one, for the file format's
// own tests; the fields those tests vary (where the tooth is, how it was made, the parameter text)
// are the caller's.
inline SessionInfo fullSessionInfo(const std::string& tooth_file, const std::string& tooth_source,
                                   const std::string& params_json) {
  SessionInfo info;
  info.created_utc = "2026-11-22T10:21:44Z";
  info.program = "dentsim 0.1.0";
  info.rate_hz = 1000.0;
  info.task = "caries_removal";
  info.tooth_hash = "0123456789abcdef";
  info.tooth_file = tooth_file;
  info.tooth_source = tooth_source;
  info.tooth_level = 9;
  info.voxel_mm = 0.034;
  info.drill_tool = "round_bur_010";
  info.mirror_tool = "mirror";
  info.params_json = params_json;
  return info;
}

}  // namespace dentsim::test
