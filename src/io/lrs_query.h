// Reading statements back from a school's LRS: one xAPI GET /statements query, filtered by activity and time, followed page by page through "more".
//
// `dentsim report --lrs` reads a class's statements with it (app/cmd_report.cpp); dentsim keeps no
// server of its own, the LRS is the class's shared store. Requests are io/lrs_client.h's getFromLrs,
// with its credentials and timeouts. Everything the LRS answers is data: errors quote it escaped.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "io/lrs_client.h"

namespace dentsim {

// The filters of GET <endpoint>/statements (xAPI 1.0.3, part 3, 2.1.3), each left out when empty.
struct StatementQuery {
  std::string activity;             // an activity IRI: the statements about it
  bool related_activities = false;  // also those that name it as context (a course as the parent of its tasks)
  std::string since;                // ISO 8601 UTC timestamp: only statements the LRS *stored* after it (exclusive)
  int page_limit = 0;               // statements per page, [1, kMaxStatementPageLimit]; 0: the LRS decides
  bool ascending = true;            // oldest stored first, so that statements read in the order they were sent
};
constexpr int kMaxStatementPageLimit = 10000;

// What fetchStatements read.
struct FetchedStatements {
  std::vector<nlohmann::ordered_json> statements;  // every page's, in the LRS's order
  int requests = 0;                                // GETs made: 1 + the "more" links followed
};

// "<endpoint>/statements?activity=...&related_activities=true&since=...&limit=N&ascending=true", the
// values percent-encoded; a query the endpoint URL had already comes first.
std::string statementQueryUrl(const std::string& endpoint_url, const StatementQuery& query);

// The URL of the next page: `more` as the LRS gave it, resolved against the URL just read. A path
// ("/xAPI/statements?cursor=...") keeps that URL's scheme and host; a whole URL must name the same
// scheme and host, since the credentials go with every request. An endpoint's own query (a token)
// is added when `more` lacks it. Errors: anything else (another host, not a path), one line.
Result<std::string> nextPageUrl(const std::string& current_url, const std::string& endpoint_url, const std::string& more);

// Every statement the query selects, page after page until "more" is empty. Errors, one line each,
// the URL shown by urlForMessage: no answer ("not reachable: ..."), an answer other than 200 ("HTTP
// 401 (Unauthorised)"), a body that is not {"statements": [...], "more": "..."}, a "more" that
// repeats a page or leads elsewhere, more than kMaxStatementPages pages.
Result<FetchedStatements> fetchStatements(const LrsEndpoint& lrs, const StatementQuery& query);
constexpr int kMaxStatementPages = 100000;
constexpr size_t kMaxStatementPageBytes = size_t(256) << 20;  // one page's answer [B]

// Seconds since the epoch as the timestamp xAPI wants in `since`: "2026-11-27T08:15:00.250Z"
// (milliseconds, UTC).
std::string xapiTimestamp(double seconds_since_epoch);

}  // namespace dentsim
