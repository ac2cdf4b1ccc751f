// Strict JSON for hand-edited files (parameter presets, task files): one parser and the pieces of their one-line error messages.
//
// nlohmann keeps the last of two repeated keys silently; a file a teacher edits by hand must not
// change meaning that way, so the parser refuses it. Messages name the key path ("tissues.enamel.hardness").
#pragma once

#include <exception>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dentsim {

// 1..64 letters, digits, '_', '-' or '.': a name that can be a file stem (tool and task names).
bool isPlainName(const std::string& s);
// A JSON string literal of `s` for a message: ASCII on one line (escaped), at most 64 bytes of `s`.
std::string quotedForMessage(const std::string& s);
// "a.b" for a plain key, a."odd key" otherwise, so that every path stays on one line.
std::string jsonChildPath(const std::string& path, const std::string& key);
// nlohmann's message without its "[json.exception...] " tag, as one line of ASCII: its "last read"
// quotes the input, which may hold control bytes or broken UTF-8; cut to 200 bytes, since that quote
// may be the rest of the file.
std::string jsonExceptionText(const std::exception& e);
// Objects and arrays nested deeper than this are refused: no preset or task nests past a few
// levels, and a file nested 100 000 deep must cost a linear scan, not the parser's time and memory.
inline constexpr int kMaxJsonDepth = 64;
// Parses text to JSON. False with *error set for a syntax error ("invalid JSON: ..."), nesting past
// kMaxJsonDepth ("invalid JSON: nested deeper than 64 levels at line L, column C"), a number beyond
// the double range ("<path>: not a finite number (...)") or a key repeated in one object
// ("<path>: repeated key"). Memory is linear in the input at any depth.
bool parseStrictJson(const std::string& text, nlohmann::json* out, std::string* error);

// The base of a schema check: keeps the first problem as "<path>: <problem>".
class JsonSchemaReader {
 public:
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }
  // Records the problem (the first one wins) and returns false.
  bool fail(const std::string& path, const std::string& problem);
  // j must be an object whose keys are all in `known`.
  bool object(const nlohmann::json& j, const std::string& path, const std::vector<std::string>& known);

 private:
  std::string error_;
};

}  // namespace dentsim
