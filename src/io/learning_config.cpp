// The learning records' config file: strict JSON, each key checked, and the default places of the file and the outbox.
#include "io/learning_config.h"

#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "io/lrs_client.h"
#include "io/strict_json.h"

namespace dentsim {
namespace {

constexpr uint64_t kMaxConfigBytes = 64 * 1024;

bool isWebIri(const std::string& s) { return s.rfind("http://", 0) == 0 || s.rfind("https://", 0) == 0; }

std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : fallback;
}

std::string homeDir() { return envOr("HOME", "."); }

// The next code point of UTF-8 text at *i (advanced past it); -1 for a malformed or overlong sequence.
long nextCodePoint(const std::string& s, size_t* i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(*i);
  const int extra = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : -1;
  if (extra < 0 || *i + size_t(extra) >= s.size()) return -1;
  long cp = extra == 0 ? c : c & (0x3F >> extra);
  for (int k = 1; k <= extra; ++k) {
    if ((byte(*i + size_t(k)) & 0xC0) != 0x80) return -1;
    cp = (cp << 6) | (byte(*i + size_t(k)) & 0x3F);
  }
  static const long kMinOf[] = {0, 0x80, 0x800, 0x10000};
  if (cp < kMinOf[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return -1;
  *i += size_t(extra) + 1;
  return cp;
}

}  // namespace

std::string studentNameProblem(const std::string& name, size_t max_bytes) {
  if (name.empty()) return "is empty";
  if (name.size() > max_bytes) return "is longer than " + std::to_string(max_bytes) + " bytes";
  for (size_t i = 0; i < name.size();) {
    const long cp = nextCodePoint(name, &i);
    if (cp < 0) return "is not UTF-8 text";
    if (cp < 0x20 || (cp >= 0x7F && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029) return "holds a control character";
    if (cp == 0x061C || cp == 0x200E || cp == 0x200F || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069))
      return "holds a bidirectional control character";
  }
  return {};
}

Result<LearningConfig> parseLearningConfig(const std::string& text, const std::string& where) {
  nlohmann::json root;
  std::string error;
  if (!parseStrictJson(text, &root, &error)) return makeError(where, error);
  JsonSchemaReader r;
  const std::vector<std::string> keys = {"student", "student_name", "course",        "lrs",      "username",
                                         "password", "home_page",   "activity_base", "language", "outbox"};
  if (!r.object(root, "", keys)) return makeError(where, r.error());
  LearningConfig c;
  for (const auto& [key, value] : root.items()) {
    if (!value.is_string()) return makeError(where, key + ": expected a string, got " + value.type_name());
    const std::string s = value.get<std::string>();
    if (s.empty()) return makeError(where, key + ": empty");
    if (key == "course" && !isPlainName(s))
      return makeError(where, "course: " + quotedForMessage(s) + " is not a plain name (letters, digits, '_', '-', '.')");
    if (key == "lrs" && !isWebIri(s)) return makeError(where, "lrs: \"" + urlForMessage(s) + "\" does not start with http:// or https://");
    if ((key == "home_page" || key == "activity_base") && !isWebIri(s))
      return makeError(where, key + ": " + quotedForMessage(s) + " does not start with http:// or https://");
    if (key == "student" || key == "student_name") {
      const std::string problem = studentNameProblem(s, key == "student" ? kMaxStudentIdBytes : kMaxStudentNameBytes);
      if (!problem.empty()) return makeError(where, key + ": " + quotedForMessage(s) + " " + problem);
    }
    std::optional<std::string>* field = key == "student"         ? &c.student
                                        : key == "student_name"  ? &c.student_name
                                        : key == "course"        ? &c.course
                                        : key == "lrs"           ? &c.lrs
                                        : key == "username"      ? &c.username
                                        : key == "password"      ? &c.password
                                        : key == "home_page"     ? &c.home_page
                                        : key == "activity_base" ? &c.activity_base
                                        : key == "language"      ? &c.language
                                                                 : &c.outbox;
    *field = s;
  }
  return c;
}

Result<LearningConfig> loadLearningConfig(const std::string& path) {
  auto bytes = readFileBytes(path, kMaxConfigBytes);
  if (!bytes) return bytes.error();
  auto config = parseLearningConfig(std::string(bytes->begin(), bytes->end()), path);
  if (!config) return config;
  if (config->outbox && std::filesystem::path(*config->outbox).is_relative())
    config->outbox = (std::filesystem::path(path).parent_path() / *config->outbox).string();
  return config;
}

std::string defaultLearningConfigPath() {
  if (const char* env = std::getenv("DENTSIM_CONFIG"); env && *env) return env;
  const std::string base = envOr("XDG_CONFIG_HOME", homeDir() + "/.config");
  return base + "/dentsim/learning.json";
}

std::string defaultOutboxPath() {
  const std::string base = envOr("XDG_DATA_HOME", homeDir() + "/.local/share");
  return base + "/dentsim/outbox.jsonl";
}

}  // namespace dentsim
