// One xAPI statement POSTed, or one page of statements read, with libcurl: headers, credentials, timeouts, and what the answer means.
#include "io/lrs_client.h"

#include <curl/curl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <mutex>

namespace dentsim {
namespace {

// curl_global_init is not thread-safe and must run once before the first handle.
void initCurlOnce() {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

// The answer's body, kept up to a limit; past it the transfer stops (curl reports a write error).
struct BodySink {
  std::string text;
  size_t max_bytes = 0;
  bool overflowed = false;
};

size_t keepBody(char* data, size_t size, size_t count, void* user) {
  auto* sink = static_cast<BodySink*>(user);
  const size_t n = size * count;
  if (sink->text.size() + n > sink->max_bytes) {
    sink->overflowed = true;
    return 0;
  }
  sink->text.append(data, n);
  return n;
}

// What every request shares: the URL, the xAPI version, timeouts, protocols and credentials.
void setCommonOptions(CURL* curl, const LrsEndpoint& lrs, const std::string& url, curl_slist* headers, BodySink* sink) {
  curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
  curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
  curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, lrs.connect_timeout_ms);
  curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, lrs.timeout_ms);
  curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);  // timeouts without SIGALRM, safe beside the haptic thread
  curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, keepBody);
  curl_easy_setopt(curl, CURLOPT_WRITEDATA, sink);
  // Only http and https: an endpoint typed as file:// or similar must not read local files.
  curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
  if (!lrs.username.empty()) {
    curl_easy_setopt(curl, CURLOPT_HTTPAUTH, CURLAUTH_BASIC);
    curl_easy_setopt(curl, CURLOPT_USERNAME, lrs.username.c_str());
    curl_easy_setopt(curl, CURLOPT_PASSWORD, lrs.password.c_str());
  }
}

// A refusal's body is read for its reason; more than this is not a reason.
constexpr size_t kMaxRefusalBodyBytes = 64 * 1024;  // [B]
constexpr size_t kMaxReasonBytes = 1000;            // [B]

// Whether a query parameter's name suggests a secret; a harmless name that matches is only masked.
bool isCredentialName(std::string name) {
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* word : {"token", "key", "pass", "pwd", "secret", "auth", "sig", "session", "credential"})
    if (name.find(word) != std::string::npos) return true;
  // A name percent-encoded to hide from the list above is masked too.
  return name.find('%') != std::string::npos;
}

// The query with each credential-like parameter's value replaced by "***".
std::string maskQuery(const std::string& query) {
  std::string out;
  size_t start = 0;
  while (start <= query.size()) {
    size_t end = query.find_first_of("&;", start);
    if (end == std::string::npos) end = query.size();
    const std::string param = query.substr(start, end - start);
    const size_t eq = param.find('=');
    out += (eq != std::string::npos && isCredentialName(param.substr(0, eq))) ? param.substr(0, eq + 1) + "***" : param;
    if (end < query.size()) out += query[end];
    start = end + 1;
  }
  return out;
}

}  // namespace

std::string urlForMessage(const std::string& url) {
  const size_t scheme_end = url.find("://");
  const size_t host_start = scheme_end == std::string::npos ? 0 : scheme_end + 3;
  size_t authority_end = url.find_first_of("/?#", host_start);
  if (authority_end == std::string::npos) authority_end = url.size();
  std::string masked = url.substr(0, host_start);
  const std::string authority = url.substr(host_start, authority_end - host_start);
  const size_t at = authority.rfind('@');
  masked += at == std::string::npos ? authority : "***" + authority.substr(at);
  const size_t fragment = url.find('#', authority_end);
  const std::string before_fragment = url.substr(authority_end, fragment == std::string::npos ? std::string::npos : fragment - authority_end);
  const size_t query = before_fragment.find('?');
  masked += query == std::string::npos ? before_fragment : before_fragment.substr(0, query + 1) + maskQuery(before_fragment.substr(query + 1));
  if (fragment != std::string::npos) masked += "#***";
  // One line of printable ASCII: no terminal escapes, no line breaks, no bidi tricks.
  constexpr size_t kMaxShown = 200;
  std::string out;
  for (unsigned char c : masked) {
    if (out.size() >= kMaxShown) return out + "...";
    if (c < 0x20 || c >= 0x7f) {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    } else {
      out += char(c);
    }
  }
  return out;
}

std::string statementsUrl(const std::string& endpoint_url) {
  // A query ("?token=...") stays after the path: the resource is <path>/statements.
  const size_t query = endpoint_url.find_first_of("?#");
  std::string url = endpoint_url.substr(0, query);
  while (!url.empty() && url.back() == '/') url.pop_back();
  return url + "/statements" + (query == std::string::npos ? "" : endpoint_url.substr(query));
}

std::string lrsReason(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return {};
  std::string reason;
  if (const auto w = j.find("warnings"); w != j.end() && w->is_array()) {
    for (const auto& item : *w)
      if (item.is_string()) reason += (reason.empty() ? "" : "; ") + item.get<std::string>();
  }
  if (const auto m = j.find("message"); reason.empty() && m != j.end() && m->is_string()) reason = m->get<std::string>();
  if (reason.size() > kMaxReasonBytes) reason = reason.substr(0, kMaxReasonBytes) + "...";
  return reason;
}

PostOutcome postStatement(const LrsEndpoint& lrs, const std::string& statement_json) {
  initCurlOnce();
  PostOutcome out;
  CURL* curl = curl_easy_init();
  if (!curl) {
    out.detail = "libcurl could not start a request";
    return out;
  }
  const std::string url = statementsUrl(lrs.url);
  curl_slist* headers = nullptr;
  headers = curl_slist_append(headers, "X-Experience-API-Version: 1.0.3");
  headers = curl_slist_append(headers, "Content-Type: application/json");
  // Without this, curl waits a second for "100 Continue" before a larger body.
  headers = curl_slist_append(headers, "Expect:");
  // The answer's body is read only for a refusal's reason, and never reaches stdout.
  BodySink sink;
  sink.max_bytes = kMaxRefusalBodyBytes;
  setCommonOptions(curl, lrs, url, headers, &sink);
  curl_easy_setopt(curl, CURLOPT_POST, 1L);
  curl_easy_setopt(curl, CURLOPT_POSTFIELDS, statement_json.c_str());
  curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(statement_json.size()));
  const CURLcode rc = curl_easy_perform(curl);
  long status = 0;
  curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &status);
  if (rc != CURLE_OK && !(rc == CURLE_WRITE_ERROR && sink.overflowed && status > 0)) {
    out.delivery = Delivery::Unreachable;
    out.detail = curl_easy_strerror(rc);
  } else {
    // A body too long to be a reason still leaves the status: the answer stands, without its reason.
    out.http_status = status;
    const bool ok = (out.http_status >= 200 && out.http_status < 300) || out.http_status == 409;
    out.delivery = ok ? Delivery::Delivered : Delivery::Refused;
    out.detail = "HTTP " + std::to_string(out.http_status);
    if (!ok && !sink.overflowed) out.reason = lrsReason(sink.text);
  }
  curl_slist_free_all(headers);
  curl_easy_cleanup(curl);
  return out;
}

GetOutcome getFromLrs(const LrsEndpoint& lrs, const std::string& url, size_t max_body_bytes) {
  initCurlOnce();
  GetOutcome out;
  CURL* curl = curl_easy_init();
  if (!curl) {
    out.detail = "libcurl could not start a request";
    return out;
  }
  curl_slist* headers = nullptr;
  headers = curl_slist_append(headers, "X-Experience-API-Version: 1.0.3");
  headers = curl_slist_append(headers, "Accept: application/json");
  BodySink sink;
  sink.max_bytes = max_body_bytes;
  setCommonOptions(curl, lrs, url, headers, &sink);
  curl_easy_setopt(curl, CURLOPT_HTTPGET, 1L);
  const CURLcode rc = curl_easy_perform(curl);
  if (rc != CURLE_OK) {
    out.detail = sink.overflowed ? "an answer longer than " + std::to_string(max_body_bytes) + " bytes" : curl_easy_strerror(rc);
  } else {
    out.answered = true;
    curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &out.http_status);
    out.detail = "HTTP " + std::to_string(out.http_status);
    out.body = std::move(sink.text);
  }
  curl_slist_free_all(headers);
  curl_easy_cleanup(curl);
  return out;
}

}  // namespace dentsim
