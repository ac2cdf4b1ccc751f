// Sending an outbox's pending learning records to the school's LRS: one sender at a time, each statement marked sent the moment the LRS takes it, within an overall time limit.
//
// The outbox and its sent log are io/xapi_outbox.h's, the HTTP request io/lrs_client.h's; this joins
// them. What a failure means to the user (a warning after a scored attempt, an error for `outbox
// send`) is the caller's (app/learning_cli.h). docs/LEARNING_RECORDS.md.
#pragma once

#include <cstddef>
#include <string>

#include "core/result.h"
#include "io/lrs_client.h"
#include "io/xapi_outbox.h"

namespace dentsim {

struct OutboxSendResult {
  size_t delivered = 0;      // statements the LRS took in this call, now in the sent log
  size_t pending = 0;        // statements still waiting after it
  std::string problem;       // why some wait: the first failure's one line, the LRS's reason escaped in it; empty when none failed
  size_t refused = 0;        // statements the LRS refused as malformed (HTTP 400) in this call, their reasons in the refusal log
  bool busy = false;         // another process was sending this outbox: nothing was tried
  SetAsideLines set_aside;   // damaged outbox lines moved to "<outbox>.bad" first; the caller warns
};

// Sends the outbox's pending statements to `lrs`, one request each, for at most limit_ms in all
// (0: no overall limit; each request keeps its own timeouts either way). The last request gets only
// what is left, so the limit holds however slow the answer. An unreachable LRS ends the sending at
// its first statement: the rest would only wait for the same timeout. One sender at a time: `wait`
// waits for another to finish; without it, another sender at work means nothing is sent (busy).
// A statement refused with HTTP 400 (malformed, in the LRS's eyes) stays pending, and its reason
// goes to the refusal log (io/xapi_outbox.h's recordRefusal), so that `outbox status` can say why;
// the same refusal in the same words, met again on a later run, is not logged twice.
// Errors: the outbox or its lock cannot be read or written.
Result<OutboxSendResult> sendOutbox(const std::string& outbox, const LrsEndpoint& lrs, long limit_ms, bool wait);

}  // namespace dentsim
