// Helpers shared by the test suites: the real-data folder, temporary directories, running the CLI.
#pragma once

#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace dentsim::test {

// ../shared/data, or $DENTSIM_DATA_DIR; empty when neither exists.
inline std::filesystem::path dataDir() {
  if (const char* env = std::getenv("DENTSIM_DATA_DIR"); env && *env && std::filesystem::is_directory(env))
    return env;
  if (std::filesystem::is_directory(DENTSIM_DEFAULT_DATA_DIR)) return DENTSIM_DEFAULT_DATA_DIR;
  return {};
}

// A fresh directory removed at scope exit.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "dentsim-test-XXXXXX").string();
    path_ = ::mkdtemp(pattern.data());
  }
  ~TempDir() { std::error_code ec; std::filesystem::remove_all(path_, ec); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A whole file's bytes; empty when it does not read.
inline std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs the dentsim binary with `args`; returns its exit code and what it printed (stdout+stderr).
struct CommandResult {
  int exit_code = -1;
  std::string output;
};
// Runs a shell command line; returns its exit code and what it printed (stdout+stderr).
inline CommandResult runCommand(const std::string& command_line) {
  CommandResult r;
  const std::string cmd = command_line + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}
inline CommandResult runDentsim(const std::string& args) { return runCommand(std::string(DENTSIM_BINARY) + " " + args); }

// Under the sanitizers lavapipe's JIT allocates memory that LeakSanitizer can neither attribute nor
// suppress, which is why tests/CMakeLists.txt runs the GPU suite without leak checks. This run of the
// binary drives the GPU, so it gets the same setting for as long as it lives; ASan's other checks
// stay on. Later ASAN_OPTIONS entries override earlier ones.
class NoLeakCheckForGpuChild {
 public:
  NoLeakCheckForGpuChild() {
    if (const char* old = std::getenv("ASAN_OPTIONS")) {
      had_ = true;
      old_ = old;
    }
    const std::string value = old_.empty() ? "detect_leaks=0" : old_ + ":detect_leaks=0";
    ::setenv("ASAN_OPTIONS", value.c_str(), 1);
  }
  ~NoLeakCheckForGpuChild() {
    if (had_) ::setenv("ASAN_OPTIONS", old_.c_str(), 1);
    else ::unsetenv("ASAN_OPTIONS");
  }
  NoLeakCheckForGpuChild(const NoLeakCheckForGpuChild&) = delete;
  NoLeakCheckForGpuChild& operator=(const NoLeakCheckForGpuChild&) = delete;

 private:
  bool had_ = false;
  std::string old_;
};

// An X server for the window tests: xvfb-run and Xvfb both installed (Debian: xvfb xauth).
inline bool haveXvfb() {
  return std::system("command -v xvfb-run >/dev/null 2>&1 && command -v Xvfb >/dev/null 2>&1") == 0;
}
// `dentsim ARGS` inside a fresh 1280x800 virtual display, with Vulkan validation on; the GPU child
// runs without leak checks (NoLeakCheckForGpuChild).
inline CommandResult runDentsimInXvfb(const std::string& args) {
  const NoLeakCheckForGpuChild no_leak_check;
  return runCommand("DENTSIM_VALIDATION=1 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(DENTSIM_BINARY) + " " + args);
}

// Writes `bytes` to `path`, replacing it: how tests forge input files.
inline void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The CLI's failure contract: a non-zero exit, one line "dentsim: ..." naming the culprit and the
// problem, and (when `output` is given) no output file.
inline void expectCleanFailure(const CommandResult& r, const std::string& names, const std::string& problem,
                               const std::string& output = "") {
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.rfind("dentsim: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(names), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(problem), std::string::npos) << r.output;
  ASSERT_FALSE(r.output.empty());
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
  if (!output.empty()) {
    EXPECT_FALSE(std::filesystem::exists(output)) << output;
  }
}

}  // namespace dentsim::test
