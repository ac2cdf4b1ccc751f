// A read of a hostile file run first in a forked child under memory and time caps, so a file that crashes, bloats or hangs its reader ends as one line.
//
// Contents
//   1. SandboxLimits: the child's caps
//   2. SandboxNote: where the child says which file it is on
//   3. SandboxWords: how the one-line errors name the reader
//   4. runSandboxed
//
// Why: a library that reads a damaged file may assert (Debian keeps GDCM's assertions), allocate a
// forged element length of gigabytes, or loop. In a child those end the child, not dentsim. If the
// child dies, the file it was on is named; if the work fails there, its message is the answer; only
// when it succeeds does the caller read again in its own process, where the same read cannot go
// wrong. The price is reading twice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "core/result.h"

namespace dentsim {

// ---- 1. SandboxLimits -------------------------------------------------------------------------
struct SandboxLimits {
  uint64_t data_growth_bytes = 0;  // how far the child's data segment may grow past the parent's (RLIMIT_DATA) [B]
  uint64_t cpu_s = 30;             // the child's processor time (RLIMIT_CPU; SIGKILL 5 s later) [s]
  uint64_t wall_s = 90;            // the parent's wait before it kills the child [s]
};

// ---- 2. SandboxNote ---------------------------------------------------------------------------
// The work's way to name the file it is on before it touches it, so that a crash names the right
// file of a folder. In the child it writes to memory the parent reads after the child ends; a
// default-made note (the caller's own read) records nothing. Not thread-safe: one writer.
class SandboxNote {
 public:
  SandboxNote() = default;
  SandboxNote(char* slot, size_t capacity) : slot_(slot), capacity_(capacity) {}
  void file(const std::string& path);

 private:
  char* slot_ = nullptr;  // (capacity_) bytes shared with the parent; nullptr: not in a child
  size_t capacity_ = 0;
};

// ---- 3. SandboxWords --------------------------------------------------------------------------
// The errors, each "FILE: ...", in the caller's terms.
struct SandboxWords {
  std::string reader = "the reader";  // who reads, "GDCM": "<reader> did not finish reading it within N s"
  std::string slow_cause = "damaged";  // why a read may not end, in parentheses after a time limit
  std::string crashed = "damaged file: the reader stops on it";  // before " (signal N)" or " (exit code N)"
};

// ---- 4. runSandboxed --------------------------------------------------------------------------
// Runs `work` in a forked child with `limits`, its stderr sent to /dev/null, and waits for it.
// Returns Ok when the work returned Ok; the work's own error (its message cut to 2046 bytes) when
// it returned one; else one line naming the file last noted (`where` until the work notes one):
// the wall limit ran out, the processor limit ran out (SIGXCPU or SIGKILL), or the child died
// otherwise (a signal, or an exit before it reported; an allocation beyond the cap usually ends so).
// When no child can be made (mmap or fork fails) it returns Ok and the caller's own read runs
// unguarded, as it would without this check.
//
// Call it from a process with no other threads running (the command line): a forked child inherits
// only the caller's thread, and a lock another thread held stays locked in it. `work` runs in the
// child only; what it changes in memory does not reach the caller.
Status runSandboxed(const std::string& where, const SandboxLimits& limits,
                    const std::function<Status(SandboxNote&)>& work, const SandboxWords& words = {});

}  // namespace dentsim
