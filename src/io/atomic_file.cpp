// Atomic file writes and bounded reads: the only place dentsim touches POSIX file descriptors.
#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <cerrno>
#include <cstdio>
#include <cstring>

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

}  // namespace

Result<std::vector<uint8_t>> readFileBytes(const std::string& path, uint64_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return makeError(path, "cannot open: " + errnoText());
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return makeError(path, "not a regular file");
  }
  if (uint64_t(st.st_size) > max_bytes) {
    ::close(fd);
    return makeError(path, "file of " + std::to_string(st.st_size) + " bytes exceeds the limit of " +
                               std::to_string(max_bytes) + " bytes");
  }
  std::vector<uint8_t> bytes(size_t(st.st_size));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      return makeError(path, n < 0 ? "read failed: " + errnoText() : "file shrank while reading");
    }
    done += size_t(n);
  }
  ::close(fd);
  return bytes;
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
  if (std::rename(temp_path.c_str(), path.c_str()) != 0) {
    const std::string why = errnoText();
    discardTemporary(temp_path);
    return makeError(path, "cannot replace: " + why);
  }
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
