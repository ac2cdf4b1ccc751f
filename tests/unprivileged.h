// Helpers for the permission tests: running code or a command as the unprivileged user nobody, since the tests otherwise run as root, which every file mode lets in.
#pragma once

#include <grp.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

namespace dentsim::test {

// nobody and nogroup on Debian: a user that owns nothing the tests make.
inline constexpr uid_t kNobodyUid = 65534;
inline constexpr gid_t kNobodyGid = 65534;

// Why this process cannot switch to nobody, or empty when it can: only root may.
inline std::string whyNotNobody() {
  if (::geteuid() != 0) return "not running as root, so it cannot switch to the unprivileged user nobody";
  return {};
}

// The prefix that runs a command as nobody: no supplementary groups, no capabilities to inherit.
// setpriv comes with util-linux (scripts/install-deps.sh).
inline std::string asNobody() {
  return "setpriv --reuid=" + std::to_string(kNobodyUid) + " --regid=" + std::to_string(kNobodyGid) +
         " --clear-groups --inh-caps=-all ";
}

// Whether setpriv is on the PATH.
inline bool haveSetpriv() { return std::system("command -v setpriv >/dev/null 2>&1") == 0; }

// Makes `dir`, a test's temporary folder (mkdtemp makes it 0700), readable and traversable by
// everyone, so that nobody reaches the files in it; the folders above it (/tmp) already are.
inline void letEveryoneIn(const std::filesystem::path& dir) {
  std::filesystem::permissions(dir, std::filesystem::perms(0755), std::filesystem::perm_options::replace);
}

// Runs `fn` in a forked child that has become nobody, and returns what it returned (or a line
// starting with "child:" when the switch failed). The caller stays root; the child only touches
// what `fn` touches, then exits without running destructors or atexit handlers.
inline std::string inChildAsNobody(const std::function<std::string()>& fn) {
  int fds[2];
  if (::pipe(fds) != 0) return "child: no pipe";
  const pid_t pid = ::fork();
  if (pid < 0) return "child: no fork";
  if (pid == 0) {
    ::close(fds[0]);
    // Groups first, then the group id, then the user id: after setresuid there is no way back.
    std::string out;
    if (::setgroups(0, nullptr) != 0 || ::setresgid(kNobodyGid, kNobodyGid, kNobodyGid) != 0 ||
        ::setresuid(kNobodyUid, kNobodyUid, kNobodyUid) != 0)
      out = "child: cannot become nobody";
    else
      out = fn();
    size_t sent = 0;
    while (sent < out.size()) {
      const ssize_t n = ::write(fds[1], out.data() + sent, out.size() - sent);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      sent += size_t(n);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string got;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got.append(buf, size_t(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return "child: did not exit cleanly";
  return got;
}

}  // namespace dentsim::test
