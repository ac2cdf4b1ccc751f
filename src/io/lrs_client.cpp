// One xAPI statement POSTed with libcurl: headers, credentials, timeouts, and what the answer means.
#include "io/lrs_client.h"

#include <curl/curl.h>

#include <mutex>

namespace dentsim {
namespace {

// curl_global_init is not thread-safe and must run once before the first handle.
void initCurlOnce() {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

// The answer's body is not needed; swallowing it keeps it off stdout.
size_t discardBody(char*, size_t size, size_t count, void*) { return size * count; }

}  // namespace

std::string statementsUrl(const std::string& endpoint_url) {
  std::string url = endpoint_url;
  while (!url.empty() && url.back() == '/') url.pop_back();
  return url + "/statements";
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
  curl_easy_setopt(curl, CURLOPT_URL, url.c_str());
  curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
  curl_easy_setopt(curl, CURLOPT_POST, 1L);
  curl_easy_setopt(curl, CURLOPT_POSTFIELDS, statement_json.c_str());
  curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(statement_json.size()));
  curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, lrs.connect_timeout_ms);
  curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, lrs.timeout_ms);
  curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);  // timeouts without SIGALRM, safe beside the haptic thread
  curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, discardBody);
  // Only http and https: an endpoint typed as file:// or similar must not read local files.
  curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
  if (!lrs.username.empty()) {
    curl_easy_setopt(curl, CURLOPT_HTTPAUTH, CURLAUTH_BASIC);
    curl_easy_setopt(curl, CURLOPT_USERNAME, lrs.username.c_str());
    curl_easy_setopt(curl, CURLOPT_PASSWORD, lrs.password.c_str());
  }
  const CURLcode rc = curl_easy_perform(curl);
  if (rc != CURLE_OK) {
    out.delivery = Delivery::Unreachable;
    out.detail = curl_easy_strerror(rc);
  } else {
    curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &out.http_status);
    const bool ok = (out.http_status >= 200 && out.http_status < 300) || out.http_status == 409;
    out.delivery = ok ? Delivery::Delivered : Delivery::Refused;
    out.detail = "HTTP " + std::to_string(out.http_status);
  }
  curl_slist_free_all(headers);
  curl_easy_cleanup(curl);
  return out;
}

}  // namespace dentsim
