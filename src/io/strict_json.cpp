// Strict JSON for hand-edited files (presets, tasks): repeated keys refused, and one-line messages naming the key path.
#include "io/strict_json.h"

#include <set>
#include <vector>

namespace dentsim {

using json = nlohmann::json;

bool isPlainName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string quotedForMessage(const std::string& s) {
  constexpr size_t kMax = 64;
  const std::string literal = json(s.substr(0, kMax)).dump(-1, ' ', true, json::error_handler_t::replace);
  return s.size() > kMax ? literal + "..." : literal;
}

std::string jsonChildPath(const std::string& path, const std::string& key) {
  const std::string segment = isPlainName(key) ? key : quotedForMessage(key);
  return path.empty() ? segment : path + "." + segment;
}

// nlohmann's message without its "[json.exception.parse_error.101] " tag, as one line of ASCII: its
std::string jsonExceptionText(const std::exception& e) {
  std::string what = e.what();
  if (what.rfind("[json.exception.", 0) == 0) {
    const size_t end = what.find("] ");
    if (end != std::string::npos) what.erase(0, end + 2);
  }
  for (char& c : what) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) c = ' ';
    else if (u >= 0x80) c = '?';
  }
  // Its "last read" is the whole token, which for an unclosed string is the rest of the file.
  constexpr size_t kMaxShown = 200;
  if (what.size() > kMaxShown) what = what.substr(0, kMaxShown) + "...";
  return what;
}

namespace {

// The open objects and arrays during a parse: one shared stack whose key path is built only when a
// message needs it, so that memory stays linear in the input at any depth.
struct OpenValue {
  bool is_object = false;
  std::set<std::string> keys;  // keys seen so far (objects)
  std::string last_key;        // the key whose value is being parsed (objects)
};

// The path of the value being parsed inside the open values [0, n): "a.b[]".
std::string pathOf(const std::vector<OpenValue>& open, size_t n) {
  std::string path;
  for (size_t i = 0; i < n; ++i) path = open[i].is_object ? jsonChildPath(path, open[i].last_key) : path + "[]";
  return path;
}

// Where nesting first goes deeper than kMaxJsonDepth, as "line L, column C", or empty. A scan of its
// own, before nlohmann parses, so that a hostile file is refused in one linear pass over its bytes;
// brackets inside strings do not count.
std::string tooDeepAt(const std::string& text) {
  int depth = 0;
  size_t line = 1, column = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    ++column;
    if (c == '\n') {
      ++line;
      column = 0;
    }
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxJsonDepth) return "line " + std::to_string(line) + ", column " + std::to_string(column);
    } else if (c == '}' || c == ']') {
      --depth;
    }
  }
  return {};
}

}  // namespace

bool parseStrictJson(const std::string& text, json* out, std::string* error) {
  if (const std::string at = tooDeepAt(text); !at.empty()) {
    *error = "invalid JSON: nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at " + at;
    return false;
  }
  // nlohmann keeps the last of repeated keys silently; a preset edited by hand must not, so a parse
  // callback tracks the keys of each open object.
  std::vector<OpenValue> open;
  std::string duplicate;
  auto callback = [&](int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        open.push_back({event == json::parse_event_t::object_start, {}, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!open.empty()) open.pop_back();
        break;
      case json::parse_event_t::key:
        if (!open.empty() && parsed.is_string()) {
          OpenValue& o = open.back();
          o.last_key = parsed.get_ref<const std::string&>();
          if (!o.keys.insert(o.last_key).second && duplicate.empty()) duplicate = pathOf(open, open.size());
        }
        break;
      case json::parse_event_t::value:
        break;
    }
    return true;
  };
  try {
    *out = json::parse(text, callback);
  } catch (const json::parse_error& e) {
    // Syntax: nlohmann's text says where ("parse error at line 3, column 5: syntax error ...").
    *error = "invalid JSON: " + jsonExceptionText(e);
    return false;
  } catch (const json::out_of_range& e) {
    // A number literal beyond the double range ("1e999"): the open values say whose value it was.
    std::string path = "(top level)";
    if (!open.empty()) path = pathOf(open, open.size());
    *error = path + ": not a finite number (" + jsonExceptionText(e) + ")";
    return false;
  } catch (const json::exception& e) {
    *error = "invalid JSON: " + jsonExceptionText(e);
    return false;
  }
  if (!duplicate.empty()) {
    *error = duplicate + ": repeated key";
    return false;
  }
  return true;
}

bool JsonSchemaReader::fail(const std::string& path, const std::string& problem) {
  if (error_.empty()) error_ = (path.empty() ? std::string("(top level)") : path) + ": " + problem;
  return false;
}

bool JsonSchemaReader::object(const json& j, const std::string& path, const std::vector<std::string>& known) {
  if (!j.is_object()) return fail(path, std::string("expected an object, got ") + j.type_name());
  for (const auto& [key, value] : j.items()) {
    bool found = false;
    for (const std::string& k : known) found = found || k == key;
    if (found) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    return fail(jsonChildPath(path, key), "unknown key (known: " + list + ")");
  }
  return true;
}

}  // namespace dentsim
