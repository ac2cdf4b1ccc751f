// The LRS client's parts that need no LRS: the statements URL, and a port where nobody listens answering "unreachable" at once rather than hanging.
#include <gtest/gtest.h>

#include <chrono>

#include "free_port.h"
#include "io/lrs_client.h"

namespace dentsim {
namespace {

using test::freePort;

TEST(LrsClient, StatementsUrlHasOneSlash) {
  EXPECT_EQ(statementsUrl("http://127.0.0.1:8080/xapi"), "http://127.0.0.1:8080/xapi/statements");
  EXPECT_EQ(statementsUrl("http://127.0.0.1:8080/xapi/"), "http://127.0.0.1:8080/xapi/statements");
}

TEST(LrsClient, NobodyListeningIsUnreachableAtOnce) {
  LrsEndpoint lrs;
  lrs.url = "http://127.0.0.1:" + std::to_string(freePort()) + "/xapi";
  // Timeouts far longer than the bound below: a refusal must come back without waiting them out,
  // and the bound is loose enough that a loaded machine cannot reach it.
  lrs.connect_timeout_ms = lrs.timeout_ms = 120000;
  const auto t0 = std::chrono::steady_clock::now();
  const PostOutcome out = postStatement(lrs, R"({"id":"x"})");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(out.delivery, Delivery::Unreachable);
  EXPECT_EQ(out.http_status, 0);
  EXPECT_FALSE(out.detail.empty());
  EXPECT_LT(s, 60.0);  // answered by the refusal, not by a timeout
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
