// The LRS query's parts that need no LRS: the GET URL with its filters encoded, the "more" links followed only on the LRS's own host, the `since` timestamp, and a refusal's reason read from the LRS's answer.
#include <gtest/gtest.h>

#include "io/lrs_client.h"
#include "io/lrs_query.h"

namespace dentsim {
namespace {

TEST(LrsQuery, TheQueryUrlEncodesEachFilter) {
  StatementQuery q;
  q.activity = "https://school.example/xapi/courses/cons-101";
  q.related_activities = true;
  q.since = "2026-11-27T08:00:00.000Z";
  q.page_limit = 2;
  EXPECT_EQ(statementQueryUrl("http://h:8080/xAPI/", q),
            "http://h:8080/xAPI/statements?activity=https%3A%2F%2Fschool.example%2Fxapi%2Fcourses%2Fcons-101"
            "&related_activities=true&since=2026-11-27T08%3A00%3A00.000Z&limit=2&ascending=true");
  // The endpoint's own query (a token) stays first; no filter, no parameter.
  EXPECT_EQ(statementQueryUrl("http://h/xapi?token=t", StatementQuery{}), "http://h/xapi/statements?token=t&ascending=true");
}

TEST(LrsQuery, MoreIsFollowedOnlyOnTheLrsHost) {
  const std::string page = "http://h:8080/xAPI/statements?limit=2";
  // The usual answer: a path, on the same host.
  EXPECT_EQ(*nextPageUrl(page, "http://h:8080/xAPI", "/xAPI/statements?cursor=c1"), "http://h:8080/xAPI/statements?cursor=c1");
  EXPECT_EQ(*nextPageUrl(page, "http://h:8080/xAPI", "HTTP://H:8080/xAPI/statements?cursor=c1"), "HTTP://H:8080/xAPI/statements?cursor=c1");
  // The endpoint's token goes with the next page too.
  EXPECT_EQ(*nextPageUrl(page, "http://h:8080/xAPI?token=t", "/xAPI/statements?cursor=c1"),
            "http://h:8080/xAPI/statements?cursor=c1&token=t");
  // The credentials go with every request: never to another host, nor to a scheme-relative one.
  EXPECT_FALSE(nextPageUrl(page, "http://h:8080/xAPI", "http://elsewhere.example/xAPI/statements").ok());
  EXPECT_FALSE(nextPageUrl(page, "http://h:8080/xAPI", "//elsewhere.example/x").ok());
  EXPECT_FALSE(nextPageUrl(page, "http://h:8080/xAPI", "statements?cursor=c1").ok());
  const auto bad = nextPageUrl(page, "http://h:8080/xAPI", "http://bob:pw@elsewhere.example/\x1b[2J");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.message().find("pw"), std::string::npos) << bad.message();
  EXPECT_EQ(bad.message().find('\x1b'), std::string::npos) << bad.message();
}

TEST(LrsQuery, SinceIsUtcWithMilliseconds) {
  EXPECT_EQ(xapiTimestamp(0.0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(xapiTimestamp(1795853552.339), "2026-11-28T08:12:32.339Z");
  // 0.9996 s rounds up into the next second, not to ".1000".
  EXPECT_EQ(xapiTimestamp(59.9996), "1970-01-01T00:01:00.000Z");
}

TEST(LrsQuery, ARefusalsReasonIsTheLrsOwnWords) {
  EXPECT_EQ(lrsReason(R"({"errorId":"e","warnings":["Problem in 'statements.0.actor.mbox'. Received '\"a\"'","second"]})"),
            "Problem in 'statements.0.actor.mbox'. Received '\"a\"'; second");
  EXPECT_EQ(lrsReason(R"({"errorId":"e","message":"Unauthorised"})"), "Unauthorised");
  EXPECT_EQ(lrsReason("<html>busy</html>"), "");
  EXPECT_EQ(lrsReason(R"({"warnings":[1,2]})"), "");
  EXPECT_EQ(lrsReason("{\"message\":\"" + std::string(5000, 'x') + "\"}").size(), 1003u);  // 1,000 bytes and "..."
}

}  // namespace
}  // namespace dentsim
