// GET /statements against a school's LRS: the query's URL, the "more" links followed safely, each page checked before its statements are kept.
#include "io/lrs_query.h"

#include <cassert>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <set>

#include "core/text_escape.h"

namespace dentsim {
namespace {

// "scheme://authority" of a URL, the scheme and host lower-cased; empty when it has no "://".
std::string originOf(const std::string& url) {
  const size_t scheme_end = url.find("://");
  if (scheme_end == std::string::npos) return {};
  size_t end = url.find_first_of("/?#", scheme_end + 3);
  if (end == std::string::npos) end = url.size();
  std::string origin = url.substr(0, end);
  for (char& c : origin) c = char(std::tolower(static_cast<unsigned char>(c)));
  return origin;
}

// The query of a URL, without its '?' and fragment; empty when it has none.
std::string queryOf(const std::string& url) {
  const size_t q = url.find('?');
  if (q == std::string::npos) return {};
  const size_t fragment = url.find('#', q);
  return url.substr(q + 1, fragment == std::string::npos ? std::string::npos : fragment - q - 1);
}

std::string withParam(const std::string& url, const std::string& param) {
  return url + (url.find('?') == std::string::npos ? "?" : "&") + param;
}

}  // namespace

std::string statementQueryUrl(const std::string& endpoint_url, const StatementQuery& query) {
  assert(query.page_limit >= 0 && query.page_limit <= kMaxStatementPageLimit);
  std::string url = statementsUrl(endpoint_url);
  if (!query.activity.empty()) url = withParam(url, "activity=" + percentEncoded(query.activity));
  if (query.related_activities) url = withParam(url, "related_activities=true");
  if (!query.since.empty()) url = withParam(url, "since=" + percentEncoded(query.since));
  if (query.page_limit > 0) url = withParam(url, "limit=" + std::to_string(query.page_limit));
  if (query.ascending) url = withParam(url, "ascending=true");
  return url;
}

Result<std::string> nextPageUrl(const std::string& current_url, const std::string& endpoint_url, const std::string& more) {
  std::string next;
  if (more.size() > 1 && more[0] == '/' && more[1] != '/') {
    // The usual answer: a path on the LRS's own host.
    next = originOf(current_url) + more;
  } else if (!originOf(more).empty() && originOf(more) == originOf(current_url)) {
    next = more;
  } else {
    // The credentials go with every request: a link to another host would hand them over.
    return Error{"the LRS's \"more\" link \"" + urlForMessage(more) + "\" is neither a path nor a URL on the LRS's host"};
  }
  const std::string endpoint_query = queryOf(endpoint_url);
  if (!endpoint_query.empty() && queryOf(next).find(endpoint_query) == std::string::npos) next = withParam(next, endpoint_query);
  return next;
}

Result<FetchedStatements> fetchStatements(const LrsEndpoint& lrs, const StatementQuery& query) {
  const std::string where = "LRS " + urlForMessage(lrs.url);
  FetchedStatements out;
  std::set<std::string> read;  // the pages' URLs: an LRS whose "more" leads back would never end
  std::string url = statementQueryUrl(lrs.url, query);
  for (;;) {
    if (out.requests >= kMaxStatementPages) return Error{where + ": more than " + std::to_string(kMaxStatementPages) + " pages of statements"};
    if (!read.insert(url).second) return Error{where + ": its \"more\" link leads back to a page already read"};
    const GetOutcome got = getFromLrs(lrs, url, kMaxStatementPageBytes);
    ++out.requests;
    if (!got.answered) return Error{where + ": not reachable: " + got.detail};
    if (got.http_status != 200) {
      // The LRS's own words say what to fix (credentials, a filter it does not take); escaped, they are data.
      const std::string reason = lrsReason(got.body);
      return Error{where + ": HTTP " + std::to_string(got.http_status) + (reason.empty() ? "" : " (" + escapeControl(reason, 300) + ")")};
    }
    nlohmann::ordered_json page = nlohmann::ordered_json::parse(got.body, nullptr, false);
    if (page.is_discarded()) return Error{where + ": the answer to GET statements is not JSON"};
    if (!page.is_object() || !page.contains("statements") || !page["statements"].is_array())
      return Error{where + ": the answer to GET statements has no \"statements\" list"};
    for (auto& statement : page["statements"]) out.statements.push_back(std::move(statement));
    if (!page.contains("more")) break;  // xAPI asks for it; an LRS that leaves it out has no more
    if (!page["more"].is_string()) return Error{where + ": the answer's \"more\" is not a string"};
    const std::string more = page["more"].get<std::string>();
    if (more.empty()) break;
    auto next = nextPageUrl(url, lrs.url, more);
    if (!next) return Error{where + ": " + next.message()};
    url = *next;
  }
  return out;
}

std::string xapiTimestamp(double seconds_since_epoch) {
  double whole = std::floor(seconds_since_epoch);
  long ms = std::lround((seconds_since_epoch - whole) * 1000.0);
  if (ms >= 1000) {
    whole += 1.0;
    ms -= 1000;
  }
  const std::time_t t = static_cast<std::time_t>(whole);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[40];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  const std::string millis = std::to_string(1000 + ms).substr(1);  // 0..999 as three digits
  return std::string(text) + "." + millis + "Z";
}

}  // namespace dentsim
