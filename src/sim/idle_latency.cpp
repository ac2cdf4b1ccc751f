// IdleLatencyRequest: the PM QoS request file held open for as long as the loop runs.
#include "sim/idle_latency.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace dentsim {

IdleLatencyRequest::IdleLatencyRequest(int32_t microseconds, const std::string& path) {
  if (microseconds < 0) return;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    note_ = path + ": " + std::strerror(errno);
    return;
  }
  // The kernel reads the request as a binary 32-bit integer, and keeps it until the file closes.
  ssize_t wrote = -1;
  do {
    wrote = ::write(fd, &microseconds, sizeof microseconds);
  } while (wrote < 0 && errno == EINTR);
  if (wrote != ssize_t(sizeof microseconds)) {
    note_ = path + ": " + (wrote < 0 ? std::strerror(errno) : std::string("short write"));
    ::close(fd);
    return;
  }
  fd_ = fd;
  note_ = "idle CPUs held to wake within " + std::to_string(microseconds) + " us (" + path + ")";
}

IdleLatencyRequest::~IdleLatencyRequest() { release(); }

IdleLatencyRequest::IdleLatencyRequest(IdleLatencyRequest&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), note_(std::move(other.note_)) {}

IdleLatencyRequest& IdleLatencyRequest::operator=(IdleLatencyRequest&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    note_ = std::move(other.note_);
  }
  return *this;
}

void IdleLatencyRequest::release() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace dentsim
