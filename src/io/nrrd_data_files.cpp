// Reads a NRRD header as Teem's nrrd reader does (lines, fields, the three `data file` forms) to list and check the data files Teem would open.
#include "io/nrrd_data_files.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>

#include "io/atomic_file.h"
#include "io/parse_guard.h"

namespace dentsim {
namespace {

// A value from the header as it may appear in a message: escaped, shortened, quoted.
std::string shown(std::string_view text) { return "'" + escapeControl(text, 80, true) + "'"; }

Error lineError(const std::string& header_path, size_t line, const std::string& what) {
  return makeError(header_path, "line " + std::to_string(line) + ": " + what);
}

// One physical line of the header, split as Teem's airOneLine splits: at "\n", "\r" or "\r\n".
struct Line {
  std::string_view text;  // up to its first NUL byte, as Teem's C string sees it
  bool empty = false;     // nothing before its end: the header's end
  bool terminated = false;  // ended by a line break, not by the end of the text
};

class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  bool next(Line& line) {
    if (at_ >= text_.size()) return false;
    size_t end = at_;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    std::string_view whole = text_.substr(at_, end - at_);
    line.empty = whole.empty();
    line.terminated = end < text_.size();
    line.text = whole.substr(0, std::min(whole.find('\0'), whole.size()));
    at_ = end;
    if (at_ < text_.size()) at_ += (text_[at_] == '\r' && at_ + 1 < text_.size() && text_[at_ + 1] == '\n') ? 2 : 1;
    return true;
  }

 private:
  std::string_view text_;
  size_t at_ = 0;
};

// Teem's field names match without regard to case; spaces and underscores are dropped here as
// well, so that every spelling Teem might take as `data file` is checked (a spelling Teem refuses
// only makes it fail before it opens anything).
bool isDataFileField(std::string_view name) {
  std::string squeezed;
  for (char c : name)
    if (c != ' ' && c != '\t' && c != '_') squeezed += char(std::tolower(static_cast<unsigned char>(c)));
  return squeezed == "datafile";
}

// The folder Teem prefixes to a header-relative name: the header's path before its last '/', or
// "." (Teem's _nrrdSplitName).
std::string headerFolder(const std::string& header_path) {
  const size_t slash = header_path.rfind('/');
  if (slash == std::string::npos || slash + 1 == header_path.size()) return ".";
  return header_path.substr(0, slash);
}

// Teem takes "-", "/..." and "?:..." as they stand, and prefixes the folder to every other name.
bool needsFolder(std::string_view name) {
  return name.empty() || (name != "-" && !(name.size() > 1 && name[1] == ':') && name[0] != '/');
}

// One integer as sscanf's "%d" reads it after whitespace, limited to 9 digits so that Teem's own
// loop over MIN..MAX by STEP cannot overflow an int.
bool scanInt(std::string_view s, size_t& at, long& out) {
  while (at < s.size() && std::isspace(static_cast<unsigned char>(s[at]))) ++at;
  const size_t start = at;
  if (at < s.size() && (s[at] == '+' || s[at] == '-')) ++at;
  const size_t digits = at;
  while (at < s.size() && std::isdigit(static_cast<unsigned char>(s[at]))) ++at;
  if (at == digits || at - digits > 9) return false;
  out = std::strtol(std::string(s.substr(start, at - start)).c_str(), nullptr, 10);
  return true;
}

// FORMAT split where its one conversion stands: prefix, zero padding, width, suffix.
struct NameFormat {
  std::string prefix, suffix;
  bool zero_pad = false;
  int width = 0;
};

// The number printed as printf's "%[0][width]d" would print it; the format text itself never
// reaches a printf.
std::string printed(const NameFormat& f, long n) {
  std::string digits = std::to_string(n < 0 ? -n : n);
  const std::string sign = n < 0 ? "-" : "";
  const size_t width = size_t(f.width);
  if (sign.size() + digits.size() < width) {
    const size_t pad = width - sign.size() - digits.size();
    return f.zero_pad ? sign + std::string(pad, '0') + digits : std::string(pad, ' ') + sign + digits;
  }
  return sign + digits;
}

// FORMAT's one conversion: '%', an optional width of 1 to 9 (with an optional leading 0), 'd'.
// Anything else with a '%' in it is refused: Teem would print it with sprintf, or would take it
// for a name while a reader of the header would not.
bool parseFormat(std::string_view token, NameFormat& f) {
  const size_t percent = token.find('%');
  if (percent == std::string_view::npos || token.find('%', percent + 1) != std::string_view::npos) return false;
  size_t at = percent + 1;
  if (at < token.size() && token[at] == '0') {
    f.zero_pad = true;
    ++at;
  }
  if (at < token.size() && token[at] >= '1' && token[at] <= '9') f.width = token[at++] - '0';
  if (at >= token.size() || token[at] != 'd') return false;
  f.prefix = std::string(token.substr(0, percent));
  f.suffix = std::string(token.substr(at + 1));
  return true;
}

struct Scan {
  std::vector<std::string> names;  // as Teem would pass them to fopen
  bool needs_more = false;         // the text ended before the header did, and more of the file exists
};

// Reads `text` (the whole file when `whole_file`) as Teem reads a header.
Result<Scan> scanHeader(std::string_view text, bool whole_file, const std::string& header_path) {
  Scan scan;
  const std::string folder = headerFolder(header_path);
  const auto add = [&](std::string_view name, size_t line) -> Status {
    if (scan.names.size() == kNrrdMaxDataFiles)
      return lineError(header_path, line, "more than " + std::to_string(kNrrdMaxDataFiles) + " data files; dentsim reads at most that many");
    scan.names.push_back(needsFolder(name) ? folder + "/" + std::string(name) : std::string(name));
    return Ok{};
  };
  LineReader reader(text);
  Line line;
  size_t number = 0;
  bool list = false;
  while (reader.next(line)) {
    ++number;
    if (number > kNrrdMaxHeaderLines)
      return makeError(header_path, "a header of more than " + std::to_string(kNrrdMaxHeaderLines) +
                                        " lines; dentsim reads at most that many");
    if (!line.terminated && !whole_file) {  // cut by the read, not by the file
      scan.needs_more = true;
      return scan;
    }
    if (list) {  // every line to the end of the file names one data file
      if (Status s = add(line.text, number); !s) return s.error();
      continue;
    }
    if (line.empty) return scan;  // the end of the header: attached data (or nothing) follows
    if (line.text.empty() || line.text[0] == '#') continue;
    const size_t colon = line.text.find(": ");
    if (colon == std::string_view::npos || !isDataFileField(line.text.substr(0, colon))) continue;
    std::string_view value = line.text.substr(colon + 2);
    value.remove_prefix(std::min(value.find_first_not_of(" \t"), value.size()));
    if (value.find('%') != std::string_view::npos) {
      // FORMAT MIN MAX STEP [SUBDIM], the value's one '%' in FORMAT
      const size_t gap = std::min(value.find_first_of(" \t"), value.size());
      NameFormat format;
      long lo = 0, hi = 0, step = 0;
      size_t at = gap;
      if (std::count(value.begin(), value.end(), '%') != 1 || !parseFormat(value.substr(0, gap), format) ||
          !scanInt(value, at, lo) || !scanInt(value, at, hi) ||
          !scanInt(value, at, step))
        return lineError(header_path, number,
                         "data file " + shown(value) +
                             " is not Teem's FORMAT MIN MAX STEP [SUBDIM] with one %d in FORMAT (width 1 to 9 at most) "
                             "and nothing else");
      if (step == 0 || (hi - lo) / step < 0) continue;  // Teem refuses it before it opens anything
      if ((hi - lo) / step >= long(kNrrdMaxDataFiles))
        return lineError(header_path, number, "more than " + std::to_string(kNrrdMaxDataFiles) +
                                                  " data files; dentsim reads at most that many");
      const bool prefix_folder = needsFolder(value.substr(0, gap));
      for (long n = lo; step > 0 ? n <= hi : n >= hi; n += step) {
        const std::string name = format.prefix + printed(format, n) + format.suffix;
        scan.names.push_back(prefix_folder ? folder + "/" + name : name);
      }
    } else if (value.substr(0, 4) == "LIST") {
      list = true;
    } else {
      if (Status s = add(value, number); !s) return s.error();
    }
  }
  if (!whole_file) scan.needs_more = true;  // the header may go on past what was read
  return scan;
}

}  // namespace

Result<std::vector<std::string>> nrrdDataFileNames(std::string_view text, const std::string& header_path) {
  const bool cut = text.size() > kNrrdMaxHeaderBytes;
  Result<Scan> scan = scanHeader(text.substr(0, std::min(text.size(), kNrrdMaxHeaderBytes)), !cut, header_path);
  if (!scan) return scan.error();
  if (scan->needs_more)
    return makeError(header_path, "a header of more than " + std::to_string(kNrrdMaxHeaderBytes >> 20) +
                                      " MiB; dentsim reads at most that much");
  return std::move(scan->names);
}

Status checkNrrdDataFiles(const std::string& header_path) {
  // Most headers end in their first few kB; a long LIST or a long detached header is read whole.
  Result<uint64_t> size = regularFileSize(header_path);
  if (!size) return size.error();
  Result<std::vector<uint8_t>> head = readFileHead(header_path, size_t{64} << 10);
  if (!head) return head.error();
  auto asText = [](const std::vector<uint8_t>& b) { return std::string_view(reinterpret_cast<const char*>(b.data()), b.size()); };
  Result<Scan> first = scanHeader(asText(*head), head->size() >= *size, header_path);
  if (!first) return first.error();
  std::vector<std::string> names = std::move(first->names);
  if (first->needs_more) {
    head = readFileHead(header_path, kNrrdMaxHeaderBytes + 1);
    if (!head) return head.error();
    Result<std::vector<std::string>> all = nrrdDataFileNames(asText(*head), header_path);
    if (!all) return all.error();
    names = std::move(*all);
  }
  for (const std::string& name : names) {
    if (name == "-") return makeError(header_path, "its data file is standard input; name a file");
    if (Status s = requireRegularFile(name); !s) {
      // requireRegularFile's message starts with the name as given; shown here escaped.
      const std::string& why = s.message();
      const std::string reason = why.rfind(name + ": ", 0) == 0 ? why.substr(name.size() + 2) : why;
      return makeError(header_path, "data file " + escapeControl(name, 200, true) + ": " + reason);
    }
  }
  return Ok{};
}

}  // namespace dentsim
