// Sending an outbox: what an LRS takes is marked sent once, an LRS that does not answer leaves all pending, another sender means none is tried, and damaged lines are set aside first.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "free_port.h"
#include "io/outbox_sender.h"
#include "test_support.h"

namespace dentsim {
namespace {

using ojson = nlohmann::ordered_json;

ojson statement(const std::string& id) { return {{"id", id}, {"verb", {{"id", "x"}}}}; }

// A stand-in LRS on 127.0.0.1 that answers every request with 200: enough for the sender, whose
// requests are small enough to go without "Expect: 100-continue".
class TakingLrs {
 public:
  TakingLrs() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    ::listen(fd_, 8);
    thread_ = std::thread([this] { serve(); });
  }
  ~TakingLrs() {
    ::shutdown(fd_, SHUT_RDWR);
    ::close(fd_);
    thread_.join();
  }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/xapi"; }
  int requests() const { return requests_; }

 private:
  void serve() {
    for (;;) {
      const int c = ::accept(fd_, nullptr, nullptr);
      if (c < 0) return;
      // The headers, then as many body bytes as they announce.
      std::string got;
      char buf[4096];
      size_t want = std::string::npos;
      while (got.size() < want) {
        const ssize_t n = ::read(c, buf, sizeof buf);
        if (n <= 0) break;
        got.append(buf, size_t(n));
        const size_t end = got.find("\r\n\r\n");
        if (want == std::string::npos && end != std::string::npos) {
          const size_t at = got.find("Content-Length: ");
          want = end + 4 + (at == std::string::npos ? 0 : std::stoul(got.substr(at + 16)));
        }
      }
      ++requests_;
      const std::string answer = "HTTP/1.1 200 OK\r\nContent-Length: 2\r\nConnection: close\r\n\r\n[]";
      (void)!::write(c, answer.data(), answer.size());
      ::close(c);
    }
  }
  int fd_ = -1;
  int port_ = 0;
  std::atomic<int> requests_{0};
  std::thread thread_;
};

LrsEndpoint endpoint(const std::string& url) {
  LrsEndpoint lrs;
  lrs.url = url;
  return lrs;
}

TEST(OutboxSender, MarksWhatTheLrsTakesAndSendsItOnce) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  ASSERT_TRUE(appendToOutbox(outbox, statement("a")).ok());
  ASSERT_TRUE(appendToOutbox(outbox, statement("b")).ok());
  TakingLrs lrs;
  auto sent = sendOutbox(outbox, endpoint(lrs.url()), 0, false);
  ASSERT_TRUE(sent.ok()) << sent.message();
  EXPECT_EQ(sent->delivered, 2u);
  EXPECT_EQ(sent->pending, 0u);
  EXPECT_TRUE(sent->problem.empty()) << sent->problem;
  EXPECT_EQ(*readSentIds(outbox), (std::set<std::string>{"a", "b"}));
  // Nothing is left to send: a second call posts nothing.
  auto again = sendOutbox(outbox, endpoint(lrs.url()), 0, false);
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(again->delivered, 0u);
  EXPECT_EQ(lrs.requests(), 2);
}

// Nobody listens: the first statement's failure ends the sending, and both stay pending.
TEST(OutboxSender, AnLrsThatDoesNotAnswerLeavesAllPending) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  ASSERT_TRUE(appendToOutbox(outbox, statement("a")).ok());
  ASSERT_TRUE(appendToOutbox(outbox, statement("b")).ok());
  auto sent = sendOutbox(outbox, endpoint("http://127.0.0.1:" + std::to_string(test::freePort()) + "/xapi"), 2000, false);
  ASSERT_TRUE(sent.ok()) << sent.message();
  EXPECT_EQ(sent->delivered, 0u);
  EXPECT_EQ(sent->pending, 2u);
  EXPECT_FALSE(sent->problem.empty());
  EXPECT_TRUE(readSentIds(outbox)->empty());
}

TEST(OutboxSender, AnotherSenderMeansNoneIsTriedAndBadLinesAreSetAside) {
  test::TempDir dir;
  const std::string outbox = dir.file("outbox.jsonl");
  ASSERT_TRUE(appendToOutbox(outbox, statement("a")).ok());
  std::ofstream(outbox, std::ios::app) << "not a statement\n";
  {
    OutboxSenderLock other(outbox, false);
    ASSERT_TRUE(other.held());
    auto busy = sendOutbox(outbox, endpoint("http://127.0.0.1:1/xapi"), 0, false);
    ASSERT_TRUE(busy.ok()) << busy.message();
    EXPECT_TRUE(busy->busy);
    EXPECT_EQ(busy->set_aside.count, 0u);  // not even read while another sender holds it
  }
  TakingLrs lrs;
  auto sent = sendOutbox(outbox, endpoint(lrs.url()), 0, false);
  ASSERT_TRUE(sent.ok()) << sent.message();
  EXPECT_EQ(sent->set_aside.count, 1u);
  EXPECT_EQ(sent->delivered, 1u);
  // An outbox whose folder is a file cannot even be locked: an error, for the caller to word.
  std::ofstream(dir.file("blocker")) << "x";
  EXPECT_FALSE(sendOutbox(dir.file("blocker/outbox.jsonl"), endpoint(lrs.url()), 0, false).ok());
}

}  // namespace
}  // namespace dentsim
