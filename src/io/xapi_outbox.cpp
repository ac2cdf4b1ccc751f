// The learning records' outbox and sent log: JSON lines appended under a lock, never rewritten but to set bad lines aside.
#include "io/xapi_outbox.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "io/atomic_file.h"
#include "io/strict_json.h"

namespace dentsim {
namespace {

using ojson = nlohmann::ordered_json;

constexpr uint64_t kMaxOutboxBytes = 1ull << 30;  // a statement is about 2 kB: half a million attempts

// Holds an exclusive flock on "<outbox>.lock" for its lifetime, so that two dentsim processes
// (a score and an `outbox send`) do not both read the old file and each rename their own over it.
class OutboxLock {
 public:
  explicit OutboxLock(const std::string& outbox) {
    const std::string path = outbox + ".lock";
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      error_ = path + ": cannot open the outbox's lock: " + std::strerror(errno);
      return;
    }
    while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
    }
  }
  ~OutboxLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  OutboxLock(const OutboxLock&) = delete;
  OutboxLock& operator=(const OutboxLock&) = delete;
  const std::string& error() const { return error_; }

 private:
  int fd_ = -1;
  std::string error_;
};

// The file's lines, without their '\n'; none when it does not exist.
Result<std::vector<std::string>> readLines(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::vector<std::string>{};
  auto bytes = readFileBytes(path, kMaxOutboxBytes);
  if (!bytes) return bytes.error();
  std::vector<std::string> lines;
  std::string line;
  for (uint8_t b : *bytes) {
    if (b == '\n') {
      lines.push_back(std::move(line));
      line.clear();
    } else {
      line += char(b);
    }
  }
  if (!line.empty()) lines.push_back(std::move(line));  // a last line without its newline
  return lines;
}

// Why a non-empty outbox line is not a statement; empty when it is one (then *parsed holds it).
std::string lineProblem(const std::string& text, ojson* parsed) {
  *parsed = ojson::parse(text, nullptr, false);
  if (parsed->is_discarded()) return "not valid JSON";
  if (!parsed->is_object() || !parsed->contains("id") || !(*parsed)["id"].is_string()) return "not a JSON object with a string \"id\"";
  return {};
}

Result<std::vector<ojson>> readOutboxUnlocked(const std::string& outbox) {
  auto lines = readLines(outbox);
  if (!lines) return lines.error();
  std::vector<ojson> out;
  for (size_t i = 0; i < lines->size(); ++i) {
    const std::string& text = (*lines)[i];
    if (text.empty()) continue;
    ojson j;
    if (std::string problem = lineProblem(text, &j); !problem.empty()) return makeError(outbox + ":" + std::to_string(i + 1), problem);
    out.push_back(std::move(j));
  }
  return out;
}

// Appends the text to the file with one O_APPEND write and fsyncs it. Lines before it are never
// rewritten, so a crash mid-write costs at most the line being written. When the file's last line
// was torn (no '\n' at its end: a crash, a full disk), a '\n' goes first, so the torn part stays a
// line of its own (set aside as bad later) and the new line is whole.
Status appendDurably(const std::string& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return makeError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string out;
  const off_t size = ::lseek(fd, 0, SEEK_END);
  char last = '\n';
  if (size > 0 && ::pread(fd, &last, 1, size - 1) == 1 && last != '\n') out = "\n";
  out += text;
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::write(fd, out.data() + done, out.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      return makeError(path, "cannot write: " + why);
    }
    done += size_t(n);
  }
  const bool synced = ::fsync(fd) == 0;
  const std::string why = synced ? "" : std::strerror(errno);
  ::close(fd);
  if (!synced) return makeError(path, "cannot sync: " + why);
  return Ok{};
}

Result<std::set<std::string>> readSentUnlocked(const std::string& outbox) {
  auto lines = readLines(sentLogPath(outbox));
  if (!lines) return lines.error();
  std::set<std::string> ids;
  for (const std::string& line : *lines)
    if (!line.empty()) ids.insert(line);
  return ids;
}

}  // namespace

std::string sentLogPath(const std::string& outbox) { return outbox + ".sent"; }

std::string badLinesPath(const std::string& outbox) { return outbox + ".bad"; }

std::string refusalLogPath(const std::string& outbox) { return outbox + ".refused"; }

Status recordRefusal(const std::string& outbox, const std::string& id, const Refusal& refusal) {
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  ojson line = ojson::object();
  line["id"] = id;
  line["http_status"] = refusal.http_status;
  // The LRS's words are data: dump escapes them, so no byte of them can end the line.
  line["reason"] = refusal.reason;
  return appendDurably(refusalLogPath(outbox), line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
}

Result<std::map<std::string, Refusal>> readRefusals(const std::string& outbox) {
  std::error_code ec;
  if (!std::filesystem::exists(refusalLogPath(outbox), ec)) return std::map<std::string, Refusal>{};
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  auto lines = readLines(refusalLogPath(outbox));
  if (!lines) return lines.error();
  std::map<std::string, Refusal> latest;
  for (const std::string& text : *lines) {
    const ojson j = ojson::parse(text, nullptr, false);
    if (!j.is_object() || !j.contains("id") || !j["id"].is_string()) continue;
    Refusal r;
    if (j.contains("http_status") && j["http_status"].is_number_integer()) r.http_status = j["http_status"].get<long>();
    if (j.contains("reason") && j["reason"].is_string()) r.reason = j["reason"].get<std::string>();
    latest[j["id"].get<std::string>()] = std::move(r);
  }
  return latest;
}

Result<SetAsideLines> setAsideBadLines(const std::string& outbox) {
  std::error_code ec;
  if (!std::filesystem::exists(outbox, ec)) return SetAsideLines{};
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  auto lines = readLines(outbox);
  if (!lines) return lines.error();
  SetAsideLines moved;
  std::string good, bad;
  for (size_t i = 0; i < lines->size(); ++i) {
    const std::string& text = (*lines)[i];
    if (text.empty()) continue;
    ojson unused;
    const std::string problem = lineProblem(text, &unused);
    if (problem.empty()) {
      good += text + "\n";
      continue;
    }
    if (moved.count++ == 0) moved.first = outbox + ":" + std::to_string(i + 1) + ": " + problem;
    bad += text + "\n";
  }
  if (moved.count == 0) return moved;
  // Side file first: a crash between the two writes leaves a line in both, never in neither.
  if (Status st = appendDurably(badLinesPath(outbox), bad); !st) return st.error();
  if (Status st = writeFileAtomic(outbox, good); !st) return st.error();
  return moved;
}

Result<std::vector<ojson>> readOutbox(const std::string& outbox) {
  std::error_code ec;
  if (!std::filesystem::exists(outbox, ec)) return std::vector<ojson>{};
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  return readOutboxUnlocked(outbox);
}

Result<bool> appendToOutbox(const std::string& outbox, const ojson& statement) {
  assert(statement.is_object() && statement.contains("id") && statement["id"].is_string());
  const std::filesystem::path folder = std::filesystem::path(outbox).parent_path();
  std::error_code ec;
  if (!folder.empty()) std::filesystem::create_directories(folder, ec);
  if (ec) return makeError(folder.string(), "cannot create the outbox's folder: " + ec.message());
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  auto lines = readLines(outbox);
  if (!lines) return lines.error();
  // A line that is not a statement holds no id; setAsideBadLines moves it, and it never blocks recording.
  const std::string id = statement["id"].get<std::string>();
  for (const std::string& text : *lines) {
    ojson j;
    if (!text.empty() && lineProblem(text, &j).empty() && j["id"].get<std::string>() == id) return false;
  }
  if (Status st = appendDurably(outbox, statement.dump() + "\n"); !st) return st.error();
  return true;
}

OutboxSenderLock::OutboxSenderLock(const std::string& outbox, bool wait) {
  const std::string path = outbox + ".send.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error_ = path + ": cannot open the sender's lock: " + std::strerror(errno);
    return;
  }
  int rc;
  while ((rc = ::flock(fd_, wait ? LOCK_EX : LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
  }
  held_ = rc == 0;
}

OutboxSenderLock::~OutboxSenderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

Result<std::set<std::string>> readSentIds(const std::string& outbox) {
  std::error_code ec;
  if (!std::filesystem::exists(outbox, ec)) return std::set<std::string>{};
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  return readSentUnlocked(outbox);
}

Status markSent(const std::string& outbox, const std::vector<std::string>& ids) {
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  auto known = readSentUnlocked(outbox);
  if (!known) return known.error();
  std::string text;
  for (const std::string& id : ids)
    if (known->insert(id).second) text += id + "\n";
  if (text.empty()) return Ok{};
  return appendDurably(sentLogPath(outbox), text);
}

Result<std::vector<ojson>> pendingStatements(const std::string& outbox) {
  std::error_code ec;
  if (!std::filesystem::exists(outbox, ec)) return std::vector<ojson>{};
  OutboxLock lock(outbox);
  if (!lock.error().empty()) return Error{lock.error()};
  auto all = readOutboxUnlocked(outbox);
  if (!all) return all.error();
  auto sent = readSentUnlocked(outbox);
  if (!sent) return sent.error();
  std::vector<ojson> pending;
  for (ojson& s : *all)
    if (!sent->count(s["id"].get<std::string>())) pending.push_back(std::move(s));
  return pending;
}

}  // namespace dentsim
