// Where an installed dentsim finds its shared files: <the executable's folder>/../share/dentsim, as the Debian package lays them out.
//
// dentsim embeds everything it needs to run (the assets and the SPIR-V), so nothing fails when this
// folder is missing. What the package installs there is what a lab uses as files: the default course
// (share/dentsim/tasks, which `run` lists when no --course is given and the current folder holds no
// assets/tasks), and the tooth and tool meshes and the preset a teacher copies to start from. The
// folder is found from /proc/self/exe, never from the current folder, so an installed binary reads
// nothing from a source tree it happens to run in. cmake/Packaging.cmake installs the files and sets
// the relative path (DENTSIM_DATA_FROM_BINDIR) from the same install directories.
#pragma once

#include <string>

namespace dentsim::app {

// The folder of the running executable (the parent of /proc/self/exe, links resolved); empty when it
// cannot be read.
std::string executableFolder();

// `exe_folder`/../share/dentsim, normalised, when that is a folder; else empty.
std::string installedDataFolder(const std::string& exe_folder);

// The installed default course, installedDataFolder()/tasks, when that is a folder; else empty.
std::string installedCourseFolder(const std::string& exe_folder);

// What `dentsim --version` prints: "dentsim 0.1.0" and a second line naming the data folder of this
// binary, "data: /usr/share/dentsim", or "data: none beside this binary (built-in assets only)".
std::string versionText(const std::string& exe_folder);

}  // namespace dentsim::app
