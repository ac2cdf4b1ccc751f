// JSON the tests read back: a file, a file of JSON lines, and the object a command printed last.
#pragma once

#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dentsim::test {

// The file as JSON; a discarded value when it is not JSON (or does not read).
inline nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in, nullptr, false);
}

// One JSON value per non-empty line (an outbox); throws on a line that is not JSON, failing the test.
inline std::vector<nlohmann::json> readJsonLines(const std::string& path) {
  std::vector<nlohmann::json> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

// The last JSON object a command printed (the commands print nothing after it): from the first '{'.
inline nlohmann::json printedJson(const std::string& output) {
  const size_t start = output.find('{');
  if (start == std::string::npos) return nlohmann::json();
  return nlohmann::json::parse(output.substr(start), nullptr, false);
}

}  // namespace dentsim::test
