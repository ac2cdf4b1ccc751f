// The learning records on the command line: settings from flags, config and environment; the attempt hook and its warn-never-fail policy; sending; `dentsim outbox`.
#include "app/learning_cli.h"

#include <cassert>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include "app/commands.h"
#include "core/text_escape.h"
#include "eval/learning_record.h"
#include "io/file_hash.h"
#include "io/learning_config.h"
#include "io/lrs_client.h"
#include "io/outbox_sender.h"
#include "io/session_file.h"
#include "io/strict_json.h"
#include "io/xapi_outbox.h"

namespace dentsim::app {
namespace {

// Everything the flags, the config file and the environment say, merged: flags first.
struct LearningSettings {
  LearnerContext learner;
  std::string outbox;
  std::optional<LrsEndpoint> lrs;  // none: statements wait in the outbox
};

std::string envText(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// The overall time that sending after a score, demo or run may take, so that a slow LRS costs the
// student seconds, not pending x answer time; what is left waits for the next run. `outbox send`,
// asked to send, has no overall limit. DENTSIM_LRS_SEND_LIMIT_MS changes it, for tests.
constexpr long kSendLimitAfterWorkMs = 10000;  // [ms]

long sendLimitAfterWorkMs() {
  const std::string text = envText("DENTSIM_LRS_SEND_LIMIT_MS");
  char* end = nullptr;
  const long ms = text.empty() ? 0 : std::strtol(text.c_str(), &end, 10);
  return (!text.empty() && end && *end == '\0' && ms > 0) ? ms : kSendLimitAfterWorkMs;
}

// One warning for the damaged lines moved aside, naming the first: recording and sending go on with
// the good ones, and the user learns where the others went.
void warnSetAside(const std::string& outbox, const SetAsideLines& moved) {
  if (moved.count == 0) return;
  const std::string more = moved.count > 1 ? " (and " + std::to_string(moved.count - 1) + " more bad line(s))" : "";
  warn(moved.first + more + "; moved to " + badLinesPath(outbox) + ", the other statements are kept");
}

// Moves the outbox's damaged lines aside (io/xapi_outbox.h) before a statement is added.
Status setAsideBadLinesWithWarning(const std::string& outbox) {
  auto moved = setAsideBadLines(outbox);
  if (!moved) return moved.error();
  warnSetAside(outbox, *moved);
  return Ok{};
}

Result<LearningSettings> resolveSettings(const LearningCliOptions& o) {
  // A file the user named must exist; the default place may be empty.
  const bool named = !o.config.empty() || !envText("DENTSIM_CONFIG").empty();
  const std::string config_path = o.config.empty() ? defaultLearningConfigPath() : o.config;
  LearningConfig config;
  std::error_code ec;
  if (named || std::filesystem::exists(config_path, ec)) {
    auto loaded = loadLearningConfig(config_path);
    if (!loaded) return loaded.error();
    config = std::move(*loaded);
  }
  LearningSettings s;
  LearnerContext& l = s.learner;
  l.student = !o.student.empty() ? o.student : config.student.value_or("");
  // The config's names were checked as it was read; --student is checked here, before any work.
  if (!o.student.empty())
    if (const std::string problem = studentNameProblem(o.student, kMaxStudentIdBytes); !problem.empty())
      return Error{"--student: " + quotedForMessage(o.student) + " " + problem};
  // The config's display name belongs to the config's student, not to another one named by --student.
  if (config.student_name && (o.student.empty() || o.student == config.student.value_or(""))) l.student_name = *config.student_name;
  l.course = !o.course.empty() ? o.course : config.course.value_or("builtin");
  if (config.home_page) l.home_page = *config.home_page;
  if (config.activity_base) l.activity_base = *config.activity_base;
  if (config.language) l.language = *config.language;
  s.outbox = !o.outbox.empty() ? o.outbox : config.outbox.value_or(defaultOutboxPath());
  const std::string url = !o.lrs.empty() ? o.lrs : config.lrs.value_or("");
  if (!url.empty()) {
    if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0)
      return Error{"--lrs: \"" + urlForMessage(url) + "\" does not start with http:// or https://"};
    LrsEndpoint lrs;
    lrs.url = url;
    // Credentials never come from the command line, where other users could read them in the process list.
    const std::string user = envText("DENTSIM_LRS_USERNAME"), password = envText("DENTSIM_LRS_PASSWORD");
    lrs.username = !user.empty() ? user : config.username.value_or("");
    lrs.password = !password.empty() ? password : config.password.value_or("");
    s.lrs = lrs;
  }
  return s;
}

// Sends through io (io/outbox_sender.h) and warns about the damaged lines it set aside first.
Result<OutboxSendResult> sendPending(const LearningSettings& s, long limit_ms, bool wait) {
  auto sum = sendOutbox(s.outbox, *s.lrs, limit_ms, wait);
  if (!sum) return sum.error();
  warnSetAside(s.outbox, sum->set_aside);
  return sum;
}

void printSendSummary(const LearningSettings& s, const OutboxSendResult& sum) {
  if (sum.busy) {
    std::printf("learning records: another dentsim is sending %s; the pending statements go with it or the next run\n",
                s.outbox.c_str());
    return;
  }
  const std::string url = urlForMessage(s.lrs->url);  // never the credentials a URL may hold
  if (sum.delivered > 0) std::printf("learning records: %zu sent to %s\n", sum.delivered, url.c_str());
  if (sum.pending > 0)
    warn("LRS " + url + ": " + sum.problem + "; " + std::to_string(sum.pending) + " statement(s) stay pending in " + s.outbox +
         " and go with the next run");
}

// The attempt's identity: its session's bytes, or the final tooth's when no session was scored.
Result<std::string> hashHex(const std::string& path) {
  auto h = fileHash(path);
  if (!h) return h.error();
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, *h);
  return std::string(text);
}

// What names the attempt (AttemptFacts without its timestamp): its session, else its final tooth.
Result<AttemptFacts> attemptFacts(const std::string& session_file, const std::string& final_file) {
  AttemptFacts facts;
  if (!session_file.empty()) {
    auto h = hashHex(session_file);
    if (!h) return h.error();
    facts.session_hash = *h;
    facts.attempt_key = *h;
  } else {
    if (final_file.empty()) return Error{"learning record: no session or final tooth was saved to name the attempt by (give --out)"};
    auto h = hashHex(final_file);
    if (!h) return h.error();
    facts.attempt_key = *h;
  }
  return facts;
}

}  // namespace

void addLearningOptions(CLI::App* cmd, LearningCliOptions& o, const std::string& course_flag) {
  cmd->add_option("--student", o.student, "Learning records: the student's account name (default: the config's)");
  cmd->add_option(course_flag, o.course, "Learning records: the course id (default: the config's, else builtin)");
  cmd->add_option("--lrs", o.lrs, "Learning records: the LRS's xAPI endpoint (credentials: config or DENTSIM_LRS_USERNAME/PASSWORD)");
  cmd->add_option("--outbox", o.outbox, "Learning records: the outbox file (.jsonl; default: the config's, else ~/.local/share/dentsim)");
  cmd->add_option("--config", o.config, "Learning records: the config file (default: $DENTSIM_CONFIG, else ~/.config/dentsim/learning.json)");
}

Status recordAttempt(const LearningCliOptions& o, const Task& task, const nlohmann::ordered_json& report,
                     const std::string& session_file, const std::string& final_file) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  if (settings->learner.student.empty()) return Ok{};  // nobody to record it for
  auto facts = attemptFacts(session_file, final_file);
  if (!facts) return facts.error();
  facts->timestamp = utcNow();
  auto statement = buildStatement(task, report, settings->learner, *facts);
  if (!statement) return statement.error();
  // A stamped report names this statement: stamped with other files or another student, it would not.
  assert(!report.contains("statement_id") || report["statement_id"] == (*statement)["id"]);
  if (Status st = setAsideBadLinesWithWarning(settings->outbox); !st) return st.error();
  auto added = appendToOutbox(settings->outbox, *statement);
  if (!added) return added.error();
  const std::string id = (*statement)["id"].get<std::string>();
  const std::string verb = (*statement)["verb"]["id"].get<std::string>();
  std::printf("learning record %s (%s) %s %s\n", id.c_str(), verb.substr(verb.rfind('/') + 1).c_str(),
              *added ? "added to" : "already in", settings->outbox.c_str());
  return Ok{};
}

Status stampStatementId(const LearningCliOptions& o, const Task& task, nlohmann::ordered_json& report,
                        const std::string& session_file, const std::string& final_file) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  if (settings->learner.student.empty()) return Ok{};  // no statement to name
  auto facts = attemptFacts(session_file, final_file);
  if (!facts) return facts.error();
  report["statement_id"] = statementId(facts->attempt_key, task.name, settings->learner.student);
  return Ok{};
}

Result<LearnerSettings> learnerSettings(const LearningCliOptions& o) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  return LearnerSettings{settings->learner, settings->outbox, o.config.empty() ? defaultLearningConfigPath() : o.config};
}

Status checkLearningOptions(const LearningCliOptions& o) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  return Ok{};
}

void recordAttemptOrWarn(const LearningCliOptions& o, const Task& task, const nlohmann::ordered_json& report,
                         const std::string& session_file, const std::string& final_file) {
  if (Status st = recordAttempt(o, task, report, session_file, final_file); !st)
    warn("the attempt was not recorded: " + st.message());
}

void recordAttemptOrWarn(const LearningCliOptions& o, const Task& task, nlohmann::ordered_json& report,
                         const std::string& session_file, const std::string& final_file) {
  if (Status st = stampStatementId(o, task, report, session_file, final_file); !st) {
    warn("the attempt was not recorded: " + st.message());
    return;
  }
  recordAttemptOrWarn(o, task, std::as_const(report), session_file, final_file);
}

Result<LrsReadSettings> lrsForReading(const LearningCliOptions& o) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  if (!settings->lrs) return Error{"no LRS (give --lrs or \"lrs\" in the config)"};
  LrsReadSettings r;
  r.lrs = *settings->lrs;
  // A page of a few hundred statements is a few MB: more than a single statement's 6 s may be needed.
  r.lrs.timeout_ms = 30000;
  r.course = settings->learner.course;
  if (!isPlainName(r.course)) return Error{"--course: " + quotedForMessage(r.course) + " is not a plain name (letters, digits, '_', '-', '.')"};
  r.course_activity = courseActivityIri(settings->learner.activity_base, r.course);
  return r;
}

Status sendPendingIfConfigured(const LearningCliOptions& o) {
  auto settings = resolveSettings(o);
  if (!settings) return settings.error();
  if (!settings->lrs) return Ok{};
  auto sum = sendPending(*settings, sendLimitAfterWorkMs(), false);  // never wait behind another sender
  // The attempt is scored and its files written: an outbox that cannot be read costs a warning.
  if (!sum) {
    warn("the learning records were not sent: " + sum.message());
    return Ok{};
  }
  printSendSummary(*settings, *sum);
  return Ok{};
}

void addOutboxCommand(CLI::App& root, Action& action) {
  CLI::App* cmd = root.add_subcommand("outbox", "The learning records waiting for the school's LRS (docs/LEARNING_RECORDS.md)");
  cmd->require_subcommand(1);
  auto o = std::make_shared<LearningCliOptions>();
  auto add_common = [o](CLI::App* sub) {
    sub->add_option("--lrs", o->lrs, "The LRS's xAPI endpoint (default: the config's)");
    sub->add_option("--outbox", o->outbox, "The outbox file (default: the config's, else ~/.local/share/dentsim/outbox.jsonl)");
    sub->add_option("--config", o->config, "The config file (default: $DENTSIM_CONFIG, else ~/.config/dentsim/learning.json)");
  };
  CLI::App* send = cmd->add_subcommand("send", "Send the pending statements now; fails while any stay pending");
  add_common(send);
  send->callback([o, &action] {
    action = [o] {
      auto settings = resolveSettings(*o);
      if (!settings) return fail(settings.message());
      if (!settings->lrs) return fail("outbox send: no LRS (give --lrs or \"lrs\" in the config)");
      auto sum = sendPending(*settings, 0, true);
      if (!sum) return fail(sum.message());
      printSendSummary(*settings, *sum);
      if (sum->pending > 0) return 1;
      if (sum->delivered == 0) std::printf("learning records: nothing pending in %s\n", settings->outbox.c_str());
      return 0;
    };
  });
  CLI::App* status = cmd->add_subcommand("status", "How many statements the outbox holds and how many wait to be sent");
  add_common(status);
  status->callback([o, &action] {
    action = [o] {
      auto settings = resolveSettings(*o);
      if (!settings) return fail(settings.message());
      if (Status st = setAsideBadLinesWithWarning(settings->outbox); !st) return fail(st.message());
      auto all = readOutbox(settings->outbox);
      if (!all) return fail(all.message());
      auto pending = pendingStatements(settings->outbox);
      if (!pending) return fail(pending.message());
      std::printf("%s: %zu statement(s), %zu pending\n", settings->outbox.c_str(), all->size(), pending->size());
      // Why the LRS refused those still pending, in its own words: escaped, an argument, never a format.
      auto refusals = readRefusals(settings->outbox);
      if (!refusals) return fail(refusals.message());
      for (const nlohmann::ordered_json& statement : *pending) {
        const auto it = refusals->find(statement["id"].get<std::string>());
        if (it == refusals->end()) continue;
        std::printf("  %s refused by the LRS (HTTP %ld): %s\n", escapeControl(it->first).c_str(), it->second.http_status,
                    escapeControl(it->second.reason, 1000).c_str());
      }
      return 0;
    };
  });
}

}  // namespace dentsim::app
