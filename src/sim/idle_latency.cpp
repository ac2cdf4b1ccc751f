// IdleLatencyRequest: the PM QoS request file held open for as long as the loop runs.
#include "sim/idle_latency.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "core/permission_advice.h"

namespace dentsim {
namespace {

// Why the permission line may be ignored: the request only makes steps after idle faster.
constexpr const char* kOptionalNote = "; optional: the loop runs without it, with slower steps after idle";

}  // namespace

IdleLatencyRequest::IdleLatencyRequest(int32_t microseconds, const std::string& path) {
  if (microseconds < 0) return;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) {
    // A file this user may not open is what the udev rule fixes, so say which rule; anything else
    // (no such file, a container's device policy refusing even root) keeps the system's word.
    denied_ = errno == EACCES;
    note_ = denied_ ? permissionAdvice(path, RuleTakesEffect::Trigger) + kOptionalNote
                    : path + ": " + std::strerror(errno);
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
    : fd_(std::exchange(other.fd_, -1)), denied_(other.denied_), note_(std::move(other.note_)) {}

IdleLatencyRequest& IdleLatencyRequest::operator=(IdleLatencyRequest&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    denied_ = other.denied_;
    note_ = std::move(other.note_);
  }
  return *this;
}

void IdleLatencyRequest::release() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace dentsim
