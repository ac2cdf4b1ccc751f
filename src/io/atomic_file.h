// Whole-file reads with a size limit, and atomic writes (temp file, fsync, rename) so a crash never destroys the last good file.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim {

// Reads a whole file, refusing one larger than max_bytes. Errors name the path.
Result<std::vector<uint8_t>> readFileBytes(const std::string& path, uint64_t max_bytes);

// Writes bytes to `path` atomically: a temporary sibling, fsync, then rename over `path`.
Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes);
// The same for text (JSON reports, presets, sidecars): its bytes as they are.
Status writeFileAtomic(const std::string& path, const std::string& text);

// For writers that must produce the file themselves (libnifti): a temporary sibling of `path`
// that keeps its extension ("a/labels.nii.gz" -> "a/labels.tmp-<pid>-<n>.nii.gz"), then
// commitTemporary() fsyncs and renames it over `path`, or discardTemporary() removes it.
std::string temporarySibling(const std::string& path);
Status commitTemporary(const std::string& temp_path, const std::string& path);
// True when both paths exist and name the same file (links and relative forms included): an output
// that would overwrite an input.
bool sameFile(const std::string& a, const std::string& b);
void discardTemporary(const std::string& temp_path);

}  // namespace dentsim
