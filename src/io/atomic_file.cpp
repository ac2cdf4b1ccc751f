// Atomic file writes and bounded reads: the only place dentsim touches POSIX file descriptors.
#include "io/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "io/input_budget.h"

namespace dentsim {
namespace {

std::string errnoText() { return std::strerror(errno); }

// Splits "dir/name.ext1.ext2" at the first dot of the file name (not of the directory).
size_t extensionStart(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t name = slash == std::string::npos ? 0 : slash + 1;
  const size_t dot = path.find('.', name + 1);  // a leading dot is part of the name
  return dot == std::string::npos ? path.size() : dot;
}

Status syncDirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return Ok{};  // the rename happened; a directory we cannot open only weakens durability
  ::fsync(fd);
  ::close(fd);
  return Ok{};
}

// What a file that is not regular is, for the message.
const char* fileTypeName(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a plain file";
}

Status regularOrError(const std::string& path, const struct stat& st) {
  if (S_ISREG(st.st_mode)) return Ok{};
  return makeError(path, std::string("not a regular file (") + fileTypeName(st.st_mode) +
                             "); dentsim reads inputs only from regular files");
}

// Opens a regular file for reading. The path is checked before the open (a FIFO's open would block
// until a writer came) and the descriptor after it (the path may have changed in between); the
// open is non-blocking for the same reason.
Result<int> openRegular(const std::string& path, struct stat* st) {
  if (Status s = requireRegularFile(path); !s) return s.error();
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return makeError(path, "cannot open: " + errnoText());
  if (::fstat(fd, st) != 0) {
    const std::string why = errnoText();
    ::close(fd);
    return makeError(path, "cannot stat: " + why);
  }
  if (Status s = regularOrError(path, *st); !s) {
    ::close(fd);
    return s.error();
  }
  return fd;
}

// Reads exactly `n` bytes, or fails naming why.
Status readExactly(int fd, uint8_t* out, size_t n, const std::string& path) {
  size_t done = 0;
  while (done < n) {
    const ssize_t got = ::read(fd, out + done, n - done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return makeError(path, got < 0 ? "read failed: " + errnoText() : "file shrank while reading");
    done += size_t(got);
  }
  return Ok{};
}

// A temporary sibling's name, split where its pid stands: "<stem>.tmp-" and the extension.
struct TemporaryPattern {
  std::string dir;     // "" for the working directory
  std::string prefix;  // "<stem>.tmp-"
  std::string ext;     // ".nii.gz", or ""
};

TemporaryPattern temporaryPattern(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t ext = extensionStart(path);
  const size_t name = slash == std::string::npos ? 0 : slash + 1;
  return {path.substr(0, name), path.substr(name, ext - name) + ".tmp-", path.substr(ext)};
}

// The pid of a temporary sibling named "<prefix><pid>-<n><ext>", or 0 when the name is not one.
pid_t temporaryPid(const std::string& name, const TemporaryPattern& p) {
  if (name.size() <= p.prefix.size() + p.ext.size() || name.compare(0, p.prefix.size(), p.prefix) != 0 ||
      name.compare(name.size() - p.ext.size(), p.ext.size(), p.ext) != 0)
    return 0;
  const std::string middle = name.substr(p.prefix.size(), name.size() - p.prefix.size() - p.ext.size());
  const size_t dash = middle.find('-');
  if (dash == 0 || dash == std::string::npos || dash + 1 == middle.size() || dash > 9) return 0;
  for (size_t i = 0; i < middle.size(); ++i)
    if (i != dash && (middle[i] < '0' || middle[i] > '9')) return 0;
  return pid_t(std::stol(middle.substr(0, dash)));
}

}  // namespace

Status requireRegularFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return makeError(path, "cannot open: " + errnoText());
  return regularOrError(path, st);
}

Result<std::vector<uint8_t>> readFileBytes(const std::string& path, uint64_t max_bytes) {
  struct stat st {};
  Result<int> fd = openRegular(path, &st);
  if (!fd) return fd.error();
  if (uint64_t(st.st_size) > max_bytes) {
    ::close(*fd);
    return makeError(path, limitExceeded("file of " + std::to_string(st.st_size) + " bytes", max_bytes));
  }
  std::vector<uint8_t> bytes(size_t(st.st_size));
  Status read = readExactly(*fd, bytes.data(), bytes.size(), path);
  ::close(*fd);
  if (!read) return read.error();
  return bytes;
}

Result<std::vector<uint8_t>> readFileHead(const std::string& path, size_t n) {
  struct stat st {};
  Result<int> fd = openRegular(path, &st);
  if (!fd) return fd.error();
  std::vector<uint8_t> bytes(std::min<uint64_t>(n, uint64_t(st.st_size)));
  Status read = readExactly(*fd, bytes.data(), bytes.size(), path);
  ::close(*fd);
  if (!read) return read.error();
  return bytes;
}

Result<uint64_t> regularFileSize(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return makeError(path, "cannot open: " + errnoText());
  if (Status s = regularOrError(path, st); !s) return s.error();
  return uint64_t(st.st_size);
}

int removeStaleTemporaries(const std::string& path) {
  const TemporaryPattern p = temporaryPattern(path);
  DIR* dir = ::opendir(p.dir.empty() ? "." : p.dir.c_str());
  if (dir == nullptr) return 0;  // cleaning is a courtesy; a folder we cannot list keeps its files
  int removed = 0;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    const pid_t pid = temporaryPid(name, p);
    // Only a pid that names no process: a live writer (ours or another's) keeps its file.
    if (pid <= 0 || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    if (::unlink((p.dir + name).c_str()) == 0) ++removed;
  }
  ::closedir(dir);
  return removed;
}

std::string temporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};  // unique names for concurrent writers in one process
  const size_t ext = extensionStart(path);
  return path.substr(0, ext) + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
         path.substr(ext);
}

Status commitTemporary(const std::string& temp_path, const std::string& path) {
  const int fd = ::open(temp_path.c_str(), O_RDONLY);
  if (fd < 0) return makeError(path, "temporary file vanished: " + errnoText());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!synced) {
    discardTemporary(temp_path);
    return makeError(path, "fsync failed: " + errnoText());
  }
  // A rename replaces whatever has the name: as root, `-o /dev/null` would put a regular file in the
  // device's place for every program on the machine. Only a regular file (or none) is replaced.
  if (struct stat st; ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    discardTemporary(temp_path);
    return makeError(path, std::string("not a regular file (") + fileTypeName(st.st_mode) +
                               "); dentsim writes its output only to a regular file");
  }
  if (std::rename(temp_path.c_str(), path.c_str()) != 0) {
    const std::string why = errnoText();
    discardTemporary(temp_path);
    return makeError(path, "cannot replace: " + why);
  }
  removeStaleTemporaries(path);
  return syncDirectoryOf(path);
}

void discardTemporary(const std::string& temp_path) { ::unlink(temp_path.c_str()); }

Status writeFileAtomic(const std::string& path, std::span<const uint8_t> bytes) {
  const std::string temp = temporarySibling(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return makeError(path, "cannot create: " + errnoText());
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = errnoText();
      ::close(fd);
      discardTemporary(temp);
      return makeError(path, "write failed: " + why);
    }
    done += size_t(n);
  }
  if (::close(fd) != 0) {
    discardTemporary(temp);
    return makeError(path, "close failed: " + errnoText());
  }
  return commitTemporary(temp, path);
}

Status writeFileAtomic(const std::string& path, const std::string& text) {
  return writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

bool sameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec) && std::filesystem::equivalent(a, b, ec);
}

}  // namespace dentsim
