// The LRS client's parts that need no LRS: the statements URL, and a port where nobody listens answering "unreachable" at once rather than hanging.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include "io/lrs_client.h"

namespace dentsim {
namespace {

TEST(LrsClient, StatementsUrlHasOneSlash) {
  EXPECT_EQ(statementsUrl("http://127.0.0.1:8080/xapi"), "http://127.0.0.1:8080/xapi/statements");
  EXPECT_EQ(statementsUrl("http://127.0.0.1:8080/xapi/"), "http://127.0.0.1:8080/xapi/statements");
}

// A localhost port that was free a moment ago: bound, read back, closed.
int freePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

TEST(LrsClient, NobodyListeningIsUnreachableAtOnce) {
  LrsEndpoint lrs;
  lrs.url = "http://127.0.0.1:" + std::to_string(freePort()) + "/xapi";
  const auto t0 = std::chrono::steady_clock::now();
  const PostOutcome out = postStatement(lrs, R"({"id":"x"})");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(out.delivery, Delivery::Unreachable);
  EXPECT_EQ(out.http_status, 0);
  EXPECT_FALSE(out.detail.empty());
  EXPECT_LT(s, 3.5);  // within the connect timeout, whatever the refusal looks like
}

TEST(LrsClient, OnlyHttpAndHttpsAreTried) {
  LrsEndpoint lrs;
  lrs.url = "file:///etc";
  const PostOutcome out = postStatement(lrs, "{}");
  EXPECT_EQ(out.delivery, Delivery::Unreachable);
  EXPECT_EQ(out.http_status, 0);
}

}  // namespace
}  // namespace dentsim
