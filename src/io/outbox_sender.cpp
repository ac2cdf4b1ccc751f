// Sends an outbox's pending statements to an LRS under the sender lock, marking each sent as it is taken.
#include "io/outbox_sender.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/text_escape.h"

namespace dentsim {

Result<OutboxSendResult> sendOutbox(const std::string& outbox, const LrsEndpoint& lrs, long limit_ms, bool wait) {
  OutboxSenderLock sender(outbox, wait);
  if (!sender.error().empty()) return Error{sender.error()};
  OutboxSendResult sum;
  if (!sender.held()) {
    sum.busy = true;
    return sum;
  }
  // Under the lock, so that no other sender reads the outbox while it is rewritten.
  auto moved = setAsideBadLines(outbox);
  if (!moved) return moved.error();
  sum.set_aside = *moved;
  auto pending = pendingStatements(outbox);
  if (!pending) return pending.error();
  // What the refusal log says already: a refusal repeated word for word on every run is not logged again.
  auto refused_before = readRefusals(outbox);
  if (!refused_before) return refused_before.error();
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed_ms = [&] {
    return long(std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start).count());
  };
  const std::string out_of_time = "sending stopped at its limit of " + std::to_string(limit_ms) + " ms";
  for (const nlohmann::ordered_json& statement : *pending) {
    LrsEndpoint request = lrs;
    bool cut = false;  // this request was given less than its own timeout: the limit ends it
    if (limit_ms > 0) {
      const long left = limit_ms - elapsed_ms();
      if (left <= 0) {
        sum.problem = out_of_time;  // why the rest wait, whatever failed before
        break;
      }
      cut = left < request.timeout_ms;
      request.timeout_ms = std::min(request.timeout_ms, left);
      request.connect_timeout_ms = std::min(request.connect_timeout_ms, left);
    }
    const PostOutcome out = postStatement(request, statement.dump());
    if (out.delivery == Delivery::Delivered) {
      // Marked at once, so that a sender killed half-way posts none of those again.
      if (Status st = markSent(outbox, {statement["id"].get<std::string>()}); !st) return st.error();
      ++sum.delivered;
      continue;
    }
    // Kept for `outbox status`: the LRS's reason is the one thing that tells the school what to fix.
    if (out.delivery == Delivery::Refused && out.http_status == 400) {
      const std::string id = statement["id"].get<std::string>();
      const auto before = refused_before->find(id);
      if (before == refused_before->end() || before->second.http_status != out.http_status || before->second.reason != out.reason)
        if (Status st = recordRefusal(outbox, id, Refusal{out.http_status, out.reason}); !st) return st.error();
      ++sum.refused;
    }
    // The reason is the LRS's text: escaped to one line of no control bytes before it joins a message.
    const std::string detail = out.reason.empty() ? out.detail : out.detail + " (" + escapeControl(out.reason, 300) + ")";
    if (sum.problem.empty()) sum.problem = cut && out.delivery == Delivery::Unreachable ? out_of_time : detail;
    if (out.delivery == Delivery::Unreachable) break;
  }
  sum.pending = pending->size() - sum.delivered;
  return sum;
}

}  // namespace dentsim
