// The LRS client's parts that need no LRS: the statements URL, a URL's credentials masked in messages, and a port where nobody listens answering "unreachable" at once rather than hanging.
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
  // The query belongs after the resource's path, not inside it.
  EXPECT_EQ(statementsUrl("http://h/xapi/?token=t"), "http://h/xapi/statements?token=t");
}

TEST(LrsClient, UrlsInMessagesHideTheirCredentials) {
  EXPECT_EQ(urlForMessage("https://lrs.example/xapi"), "https://lrs.example/xapi");
  EXPECT_EQ(urlForMessage("http://bob:PW@h:8080/xapi"), "http://***@h:8080/xapi");
  EXPECT_EQ(urlForMessage("http://bob@h/x"), "http://***@h/x");
  // The last '@' ends the user info, as curl reads it: a password holding '@' is hidden whole.
  EXPECT_EQ(urlForMessage("http://bob:P@W@h/x"), "http://***@h/x");
  EXPECT_EQ(urlForMessage("http://h/x?Token=T1&n=2;api_key=K2&Password=P3&sig=S4&client_secret=S5"),
            "http://h/x?Token=***&n=2;api_key=***&Password=***&sig=***&client_secret=***");
  EXPECT_EQ(urlForMessage("http://h/x?n=2#access_token=T"), "http://h/x?n=2#***");
  // An '@' in the path is not user info; a name hidden by percent-encoding is masked anyway.
  EXPECT_EQ(urlForMessage("http://h/a@b?%74oken=T"), "http://h/a@b?%74oken=***");
  // Not a URL at all (a mistyped --lrs): user info before the first '/' is still hidden.
  EXPECT_EQ(urlForMessage("bob:PW@lrs.example/x"), "***@lrs.example/x");
  // One line of ASCII: no escape sequence, line break or bidi control reaches the terminal.
  EXPECT_EQ(urlForMessage("http://h/\x1b[2J\n\xe2\x80\xae"), "http://h/%1B[2J%0A%E2%80%AE");
  EXPECT_EQ(urlForMessage("http://h/" + std::string(500, 'a')).size(), 203u);
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
