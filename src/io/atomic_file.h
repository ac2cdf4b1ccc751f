// Whole-file reads with a size limit, and atomic writes (temp file, fsync, rename) so a crash never destroys the last good file.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim {

// Ok when `path` is a regular file (links followed); otherwise "<path>: not a regular file (a FIFO)"
// or "cannot open: ...". Every reader calls it (readFileBytes does) before it opens a file, so that a
// FIFO, a directory or a device given as an input is refused at once instead of blocking on open.
Status requireRegularFile(const std::string& path);
// Reads a whole regular file, refusing one larger than max_bytes (with the budget's flag named when
// max_bytes is the input budget). Never blocks on a FIFO. Errors name the path.
Result<std::vector<uint8_t>> readFileBytes(const std::string& path, uint64_t max_bytes);
// The first min(n, size) bytes of a regular file, for a look at its kind or its header before the
// whole file is read.
Result<std::vector<uint8_t>> readFileHead(const std::string& path, size_t n);
// The size of a regular file [B].
Result<uint64_t> regularFileSize(const std::string& path);

// Writes bytes to `path` atomically: a temporary sibling, fsync, then rename over `path`.
Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes);
// The same for text (JSON reports, presets, sidecars): its bytes as they are.
Status writeFileAtomic(const std::string& path, const std::string& text);

// For writers that must produce the file themselves (libnifti): a temporary sibling of `path`
// that keeps its extension ("a/labels.nii.gz" -> "a/labels.tmp-<pid>-<n>.nii.gz"), then
// commitTemporary() fsyncs and renames it over `path`, or discardTemporary() removes it. Every
// error path discards it; only a killed process leaves one behind, and the next commit of `path`
// removes it (removeStaleTemporaries).
std::string temporarySibling(const std::string& path);
Status commitTemporary(const std::string& temp_path, const std::string& path);
// Removes the temporary siblings of `path` ("<stem>.tmp-<pid>-<n><ext>") whose writing process no
// longer exists (kill(pid, 0) fails with ESRCH); a live process's temporary is kept. Returns how
// many were removed.
int removeStaleTemporaries(const std::string& path);
// True when both paths exist and name the same file (links and relative forms included): an output
// that would overwrite an input.
bool sameFile(const std::string& a, const std::string& b);
void discardTemporary(const std::string& temp_path);

}  // namespace dentsim
