// Confining the paths a file names (a session's tooth, a task's tooth and ideal) to that file's own folder, so that a downloaded file cannot make dentsim open /etc/passwd or ../../anything.
#pragma once

#include <string>

#include "core/result.h"

namespace dentsim {

// Resolves `named`, a path that the file `owner` holds in its header (a session's tooth file, a
// task's tooth), against owner's folder, and returns it only when it lies in that folder or below
// it. Absolute paths and ".." that climb out (after following links, by weakly_canonical) are
// refused. `what` names the field in the message ("tooth.file", "tooth"). The message names the
// owner, the field and the refused path, and never reads the file it names, so nothing of that file
// is echoed. The file need not exist (its reader says so).
Result<std::string> resolveBeside(const std::string& owner, const std::string& named, const std::string& what);

// True when `path` lies in `folder` or below it, after both are made absolute and canonical as far
// as they exist (links followed).
bool liesWithin(const std::string& path, const std::string& folder);

// Copies `from` to `to` through a temporary sibling, so that `to` is whole or untouched; nothing
// when both name the same file.
Status copyFileAtomic(const std::string& from, const std::string& to);

// The name by which the file `owner` (a task being written) names `path`, relative to owner's
// folder. A file that lies outside that folder is first copied into it under its own file name
// (`*copied` set), so that the folder holds everything it names and can be copied whole; a
// different file already there under that name is an error naming both.
Result<std::string> nameBeside(const std::string& owner, const std::string& path, bool* copied);

}  // namespace dentsim
