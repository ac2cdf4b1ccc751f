// The forked, capped child that runs a hostile read first (io/sandboxed_read.h says why).
#include "io/sandboxed_read.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <thread>

namespace dentsim {
namespace {

// The page the parent and the child share: plain bytes, as the child may die mid-write.
struct ChildReport {
  char outcome = '?';  // '?' running or died, 'E' an error (message), 'K' done
  char message[2047] = {};
  char current_file[2048] = {};
};

void copyInto(char* dst, size_t cap, const std::string& src) {
  const size_t n = std::min(src.size(), cap - 1);
  std::memcpy(dst, src.data(), n);
  dst[n] = '\0';
}

// The data segment's size now [B], from /proc/self/status (VmData); 0 when unknown. The cap is set
// above it, since the child starts with all of the parent's heap.
uint64_t dataSegmentBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmData:", 0) == 0) return uint64_t(std::strtoull(line.c_str() + 7, nullptr, 10)) * 1024;
  return 0;
}

// Waits for `child` until `wall_s` have passed, then kills it; true when it ended by itself. The
// naps grow to 50 ms, so a quick child costs a millisecond and a slow one little processor time.
bool waitWithin(pid_t child, uint64_t wall_s, int& status) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(wall_s);
  auto nap = std::chrono::milliseconds(1);
  for (;;) {
    const pid_t done = ::waitpid(child, &status, WNOHANG);
    if (done == child || (done < 0 && errno != EINTR)) return true;
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(nap);
    nap = std::min(nap * 2, std::chrono::milliseconds(50));
  }
  ::kill(child, SIGKILL);
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  return false;
}

[[noreturn]] void runChild(ChildReport* report, uint64_t data_now, const SandboxLimits& limits,
                           const std::function<Status(SandboxNote&)>& work) {
  // The library's own complaints (an assertion's text) are not the user's business: the parent
  // prints the one line.
  if (const int null_fd = ::open("/dev/null", O_WRONLY); null_fd >= 0) ::dup2(null_fd, STDERR_FILENO);
  if (data_now > 0) {
    const rlimit cap{rlim_t(data_now + limits.data_growth_bytes), rlim_t(data_now + limits.data_growth_bytes)};
    ::setrlimit(RLIMIT_DATA, &cap);
  }
  const rlimit cpu{rlim_t(limits.cpu_s), rlim_t(limits.cpu_s + 5)};  // SIGXCPU, then SIGKILL 5 s later
  ::setrlimit(RLIMIT_CPU, &cpu);
  SandboxNote note(report->current_file, sizeof report->current_file);
  const Status s = work(note);
  if (s) {
    report->outcome = 'K';
  } else {
    copyInto(report->message, sizeof report->message, s.message());
    report->outcome = 'E';
  }
  ::_exit(0);  // no atexit handlers or buffered output of the parent's run twice
}

}  // namespace

void SandboxNote::file(const std::string& path) {
  if (slot_) copyInto(slot_, capacity_, path);
}

Status runSandboxed(const std::string& where, const SandboxLimits& limits,
                    const std::function<Status(SandboxNote&)>& work, const SandboxWords& words) {
  void* shared = ::mmap(nullptr, sizeof(ChildReport), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (shared == MAP_FAILED) return Ok{};  // no check possible: the caller reads unguarded
  auto* report = new (shared) ChildReport;
  copyInto(report->current_file, sizeof report->current_file, where);
  const uint64_t data_now = dataSegmentBytes();
  std::fflush(nullptr);  // what the parent printed goes out before the wait, not after it
  const pid_t child = ::fork();
  if (child == 0) runChild(report, data_now, limits, work);
  int status = 0;
  const bool ended = child > 0 ? waitWithin(child, limits.wall_s, status) : true;
  const char outcome = child > 0 ? report->outcome : 'K';  // fork failed: the caller reads unguarded
  const std::string file(report->current_file), message(report->message);
  ::munmap(shared, sizeof(ChildReport));
  if (outcome == 'K') return Ok{};
  if (outcome == 'E') return Error{message};
  if (!ended)
    return makeError(file, words.reader + " did not finish reading it within " + std::to_string(limits.wall_s) +
                               " s (" + words.slow_cause + ")");
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL))
    return makeError(file, words.reader + " took more than " + std::to_string(limits.cpu_s) +
                               " s of processor time on it (" + words.slow_cause + ")");
  const std::string how = WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                              : "exit code " + std::to_string(WEXITSTATUS(status));
  return makeError(file, words.crashed + " (" + how + ")");
}

}  // namespace dentsim
