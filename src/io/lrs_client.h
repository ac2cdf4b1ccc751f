// The HTTP side of the learning records: one xAPI statement POSTed to a school's LRS, or one page of statements read from it, through libcurl, with short timeouts and Basic credentials.
//
// The caller decides what a failure means for its outbox (io/outbox_sender.h): delivered
// statements are marked sent; refused or unreachable ones stay pending for the next run. Reading
// a class's statements page by page is io/lrs_query.h's.
#pragma once

#include <string>

namespace dentsim {

struct LrsEndpoint {
  std::string url;                // the xAPI endpoint ("https://lrs.school.example/xapi"); statements go to <url>/statements
  std::string username, password; // HTTP Basic credentials; empty username: none sent
  long connect_timeout_ms = 3000; // a dead host costs at most this [ms]
  long timeout_ms = 6000;         // the whole request, answer included [ms]
};

enum class Delivery {
  Delivered,    // 2xx, or 409 (the LRS holds a statement with this id already): never send it again
  Refused,      // any other answer: the LRS is up but will not take it now (auth, 5xx, bad request)
  Unreachable,  // no answer at all: down, no route, timeout; the later statements need not be tried
};

struct PostOutcome {
  Delivery delivery = Delivery::Unreachable;
  long http_status = 0;  // 0 without an answer
  std::string detail;    // one line: "HTTP 401", "Connection refused", ...
  std::string reason;    // a refusal's reason as the LRS gave it (lrsReason); raw data from outside, never a format
};

// What an LRS said about a refused request, from its answer's body: the "warnings" strings (joined
// by "; ") when the body is a JSON object that has them, else its "message" string, else empty.
// Raw text from the LRS, cut to 1,000 bytes: the caller escapes it wherever it shows it.
std::string lrsReason(const std::string& body);

// One GET's answer.
struct GetOutcome {
  bool answered = false;  // false: no answer at all (down, no route, timeout, too long a body)
  long http_status = 0;   // 0 without an answer
  std::string body;       // the answer's body, at most max_body_bytes
  std::string detail;     // one line: "HTTP 401", "Connection refused", ...
};

// "<url>/statements" with exactly one '/' between, before the URL's query if it has one.
std::string statementsUrl(const std::string& endpoint_url);

// THE way a URL goes into any message, line or page: credentials masked, the rest made one safe line.
// User info becomes "***" ("http://bob:pw@h/x" -> "http://***@h/x"); so does the value of every query
// parameter whose name (any case) holds token, key, pass, pwd, secret, auth, sig, session or
// credential ("?token=abc&n=2" -> "?token=***&n=2"), and a whole fragment. Control and non-ASCII bytes
// become %XX, and a URL past 200 characters is cut with "...". Works on text that is not a URL too.
std::string urlForMessage(const std::string& url);

// POSTs one statement (its JSON text) with "X-Experience-API-Version: 1.0.3" and
// "Content-Type: application/json".
PostOutcome postStatement(const LrsEndpoint& lrs, const std::string& statement_json);

// GETs `url` (a whole URL: the caller builds it, io/lrs_query.h) with "X-Experience-API-Version:
// 1.0.3", "Accept: application/json" and the endpoint's credentials and timeouts. An answer longer
// than max_body_bytes is no answer (detail says so).
GetOutcome getFromLrs(const LrsEndpoint& lrs, const std::string& url, size_t max_body_bytes);

}  // namespace dentsim
