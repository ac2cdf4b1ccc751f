// The data files a NRRD header makes Teem open, found by reading the header as Teem reads it, so each can be checked a regular file before Teem opens any.
//
// Contents
//   1. Limits
//   2. nrrdDataFileNames: the header's text to the paths Teem would open
//   3. checkNrrdDataFiles: a header file's data files, each a regular file
//
// Why: Teem opens a detached header's data files even to read the header alone, and opens them
// blocking: standard input ("-"), a FIFO or a device would hang it. And Teem hands the `data file`
// format (FORMAT MIN MAX STEP [SUBDIM]) to sprintf, so a format of anything but one %d would let
// the file's text write memory. So the whole header is read here first, by Teem's rules:
//   - a line ends at "\n", "\r" or "\r\n"; a line's text ends at its first NUL byte;
//   - the header ends at the first empty line (attached data follows) or at the end of the file;
//   - a line starting '#' is a comment; a field is the text before the first ": ", its value the
//     rest after spaces and tabs;
//   - `data file: NAME` names one file (NAME is the whole rest of the line, spaces included);
//     `data file: LIST [SUBDIM]` names one file a line on every line after it, to the end of
//     the file; `data file: FORMAT MIN MAX STEP [SUBDIM]` names FORMAT printed with MIN, MIN+STEP,
//     ... up to MAX;
//   - a name is relative to the header's folder unless it starts with '/' or its second
//     character is ':' (then Teem takes it as it stands); "-" is standard input.
// Stricter than Teem, so that what passes is what Teem reads safely: any '%' in a `data file`
// value (other than a LIST's names, which Teem never prints with) must be exactly one %d with
// an optional width of 1 to 9 ("%d", "%03d"); MIN, MAX and STEP have at most 9 digits.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace dentsim {

// ---- 1. Limits --------------------------------------------------------------------------------
// Far beyond any scan's header (a few dozen lines, one data file per slice at most), and small
// enough that reading them is quick; a header past them is refused before Teem opens anything.
constexpr size_t kNrrdMaxHeaderLines = 100000;            // lines read, comments and LIST names included
constexpr size_t kNrrdMaxDataFiles = 65536;               // files one header may name
constexpr size_t kNrrdMaxHeaderBytes = size_t{16} << 20;  // bytes read before the header ends [B]

// ---- 2. nrrdDataFileNames ---------------------------------------------------------------------
// The paths Teem would open for the header `text` of the file `header_path` (as given to Teem: its
// folder is the part before the last '/', else "."), in Teem's order; empty for attached data.
// `text` holds the header's bytes, or the file's first bytes (the header ends at its empty line).
// Errors are one line naming `header_path`, the line and the problem, with the file's text escaped.
// `text` longer than kNrrdMaxHeaderBytes without the header's end is refused as too long.
Result<std::vector<std::string>> nrrdDataFileNames(std::string_view text, const std::string& header_path);

// ---- 3. checkNrrdDataFiles ---------------------------------------------------------------------
// Reads the header of `header_path` (at most kNrrdMaxHeaderBytes) and checks that every data file
// Teem would open is a regular file and not standard input. One line naming the header and the
// data file (escaped) otherwise.
Status checkNrrdDataFiles(const std::string& header_path);

}  // namespace dentsim
