// The learning records' config file: strict JSON, each key checked, and the default places of the file and the outbox.
#include "io/learning_config.h"

#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
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

}  // namespace

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
    if ((key == "lrs" || key == "home_page" || key == "activity_base") && !isWebIri(s))
      return makeError(where, key + ": " + quotedForMessage(s) + " does not start with http:// or https://");
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
