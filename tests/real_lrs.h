// A real LRS for the learning-record tests: Learning Locker's statement service (npm xapi-statements, tests/lrs), started on a free port for one test and stopped after it.
//
// It runs as a separate process (GPL-3 test server, never linked), in memory, with no database.
// tests/lrs/run_lrs.js puts it behind a client lookup that knows one user and password, so that a
// request without them is refused (401) and every statement it stores carries, as its authority,
// the account of the credentials that sent it. A test skips with missing()'s line when node or the
// package is not installed (scripts/install-deps.sh installs both).
#pragma once

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "free_port.h"
#include "test_support.h"

namespace dentsim::test {

class RealLrs {
 public:
  // The user and password the LRS takes; the fixture's dentsim runs are given the same ones.
  RealLrs(const TempDir& dir, const std::string& name, const std::string& username, const std::string& password)
      : folder_(dir.file(name)), username_(username), password_(password) {
    const std::filesystem::path tools = std::filesystem::path(DENTSIM_SOURCE_DIR) / "tests" / "lrs";
    if (!missing().empty()) return;
    std::filesystem::create_directories(folder_);
    const std::string ready = folder_ + "/ready";
    // A port free a moment ago may be taken by the time node binds it (a test beside this one):
    // the server then exits at once, and another port is tried.
    for (int attempt = 0; attempt < 3 && !up_; ++attempt) {
      port_ = freePort();
      // In its own folder, where it keeps its access log; `exec`, so that the pid is node's own.
      // It watches this test's pid and ends with it.
      const auto r = runCommand("(cd '" + folder_ + "' && exec node " + (tools / "run_lrs.js").string() + " " + std::to_string(port_) +
                                " '" + username + "' '" + password + "' " + std::to_string(::getpid()) + " " + ready +
                                ") >>'" + folder_ + "/lrs.out' 2>&1 & echo $!");
      pid_ = std::atoi(r.output.c_str());
      // Node's start takes about half a second; a loaded machine can stretch it: up to 60 s, which
      // only an LRS that never comes up waits out.
      for (int i = 0; i < 1200 && !std::filesystem::exists(ready) && alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      up_ = std::filesystem::exists(ready);
    }
  }
  ~RealLrs() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
  }
  RealLrs(const RealLrs&) = delete;
  RealLrs& operator=(const RealLrs&) = delete;

  // Why a test of it cannot run here; empty when node and the package are installed. Asked before
  // starting one: a test skips with this line.
  static std::string missing() {
    if (runCommand("node --version").exit_code != 0) return "node is not installed: the real LRS (tests/lrs) cannot run";
    if (!std::filesystem::exists(std::filesystem::path(DENTSIM_SOURCE_DIR) / "tests" / "lrs" / "node_modules" / "xapi-statements" /
                                 "dist" / "server.js"))
      return "xapi-statements is not installed in tests/lrs (scripts/install-deps.sh runs npm ci there)";
    return {};
  }
  bool up() const { return up_; }
  // What its stderr said, for a failure's message.
  std::string log() const {
    std::ifstream in(folder_ + "/lrs.out");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  // The xAPI endpoint, as a school gives it to dentsim.
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/xAPI"; }

  // Every statement it holds, oldest stored first, read by the tests' own reader (tests/lrs/read_statements.js),
  // `page` at a time; empty, with the reason in *error, when the read fails.
  std::vector<nlohmann::json> statements(std::string* error = nullptr, int page = 0) const {
    const auto r = runCommand("node " + (std::filesystem::path(DENTSIM_SOURCE_DIR) / "tests" / "lrs" / "read_statements.js").string() +
                              " " + url() + " '" + username_ + "' '" + password_ + "'" + (page > 0 ? " " + std::to_string(page) : ""));
    const nlohmann::json all = nlohmann::json::parse(r.output, nullptr, false);
    if (r.exit_code != 0 || !all.is_array()) {
      if (error) *error = r.output;
      return {};
    }
    return std::vector<nlohmann::json>(all.begin(), all.end());
  }

  // The requests its access log holds with this method, path prefix and status ("POST",
  // "/xAPI/statements", 200): the service's own count of what reached it. The log is written after
  // each answer is sent, so a GET /xAPI/about is asked first and waited for in the log: the lines
  // of every earlier request come before it.
  int requests(const std::string& method, const std::string& path, int status) const {
    const int barriers = countLines("GET", "/xAPI/about", 200);
    runCommand("node -e \"require('http').get('http://127.0.0.1:" + std::to_string(port_) + "/xAPI/about', (r) => r.resume())\"");
    for (int i = 0; i < 1200 && countLines("GET", "/xAPI/about", 200) <= barriers; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return countLines(method, path, status);
  }

 private:
  // Whether the server process is still there (a zombie reaped by no one counts as gone).
  bool alive() const {
    if (pid_ <= 0 || ::kill(pid_, 0) != 0) return false;
    std::ifstream stat("/proc/" + std::to_string(pid_) + "/stat");
    std::string pid, name, state;
    stat >> pid >> name >> state;
    return state != "Z";
  }

  int countLines(const std::string& method, const std::string& path, int status) const {
    int n = 0;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder_ + "/storage/accessLogs", ec)) {
      std::ifstream in(entry.path());
      // "POST /xAPI/statements ::ffff:127.0.0.1 - <date> {} 200"
      const std::string tail = " " + std::to_string(status);
      for (std::string line; std::getline(in, line);)
        if (line.rfind(method + " " + path, 0) == 0 && line.size() > tail.size() && line.substr(line.size() - tail.size()) == tail) ++n;
    }
    return n;
  }

  std::string folder_, username_, password_;
  int port_ = 0;
  int pid_ = 0;
  bool up_ = false;
};

}  // namespace dentsim::test
