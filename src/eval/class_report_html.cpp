// Writes the class report's page: HTML tables, SVG progress plots and histograms, pictures inlined as base64 PNG.
//
// Contents: 1. text helpers  2. the progress plot  3. the histogram  4. the points lost  5. the page
#include "eval/class_report_html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "core/text_escape.h"
#include "eval/task_kinds.h"

namespace dentsim {

// ---- 1. text helpers ------------------------------------------------------------------------------

std::string htmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    // Three bytes make four six-bit digits; a short tail is padded with '='.
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = uint32_t(bytes[i]) << 16;
    if (n > 1) v |= uint32_t(bytes[i + 1]) << 8;
    if (n > 2) v |= uint32_t(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += n > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out += n > 2 ? kAlphabet[v & 63] : '=';
  }
  return out;
}

namespace {

// The ways the page writes a time (UTC), each a literal strftime format: no format is built at run time.
enum class TimeShown { DayAndClock, Day, MonthDay, Clock, MonthDayClock };

std::string timeText(double time_s, TimeShown shown) {
  const auto t = std::time_t(std::floor(time_s));
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char text[64];
  switch (shown) {
    case TimeShown::DayAndClock: std::strftime(text, sizeof text, "%Y-%m-%d %H:%M", &tm); break;
    case TimeShown::Day: std::strftime(text, sizeof text, "%F", &tm); break;
    case TimeShown::MonthDay: std::strftime(text, sizeof text, "%m-%d", &tm); break;
    case TimeShown::Clock: std::strftime(text, sizeof text, "%H:%M", &tm); break;
    case TimeShown::MonthDayClock: std::strftime(text, sizeof text, "%m-%d %H:%M", &tm); break;
  }
  return text;
}

// What the page writes where a value is not known.
constexpr const char* kNone = "\u2014";

std::string num(double v, int digits = 1) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

// A name or title from a file as the page shows it: at most 120 bytes (cut between characters, with
// an ellipsis), so that a 100 kB name cannot make the page millions of pixels wide.
std::string shortened(const std::string& text) {
  constexpr size_t kMaxBytes = 120;
  if (text.size() <= kMaxBytes) return text;
  size_t end = kMaxBytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;  // not inside a UTF-8 sequence
  return text.substr(0, end) + "\u2026";
}

// The same between U+2068 and U+2069 (first-strong isolate, pop isolate), for attributes and SVG
// text where <bdi> cannot go: its own bidi controls cannot reorder the text after it (an unclosed
// right-to-left override made "76.1" read "1.67").
std::string isolated(const std::string& text) { return "\u2068" + shortened(text) + "\u2069"; }

// The same for HTML: escaped, in <bdi>.
std::string bdi(const std::string& text) { return "<bdi>" + htmlEscape(shortened(text)) + "</bdi>"; }

}  // namespace

std::string utcText(double time_s) { return timeText(time_s, TimeShown::DayAndClock); }

std::string studentColour(size_t i) {
  // Ten colours that stay apart on screen and in print.
  static constexpr const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kPalette[i % 10];
}

// ---- 2. the progress plot -------------------------------------------------------------------------

namespace {

// Plot geometry [px]: the axes' box inside the SVG, room on the right for the legend.
constexpr double kWidth = 720, kHeight = 300;
constexpr double kLeft = 50, kRight = 560, kTop = 20, kBottom = 250;

double yOf(double score) { return kBottom - (kBottom - kTop) * std::clamp(score, 0.0, 100.0) / 100.0; }

// Time ticks: the smallest step from this ladder that gives at most six ticks over the span [s].
double tickStep(double span_s) {
  static constexpr double kSteps[] = {60,     300,     900,     1800,     3600,      3 * 3600, 6 * 3600,
                                      43200,  86400,   2 * 86400, 7 * 86400, 14 * 86400, 28 * 86400, 91 * 86400};
  for (double s : kSteps)
    if (span_s / s <= 6.0) return s;
  return std::ceil(span_s / 6.0 / 86400.0) * 86400.0;
}

void scoreAxis(std::string& svg, const std::string& label) {
  for (int s = 0; s <= 100; s += 20) {
    const std::string y = num(yOf(s));
    svg += "<line class=\"grid\" x1=\"" + num(kLeft) + "\" x2=\"" + num(kRight) + "\" y1=\"" + y + "\" y2=\"" + y + "\"/>";
    svg += "<text class=\"tick\" x=\"" + num(kLeft - 6) + "\" y=\"" + y + "\" text-anchor=\"end\" dominant-baseline=\"middle\">" +
           std::to_string(s) + "</text>";
  }
  svg += "<text class=\"axis-label\" transform=\"translate(14," + num((kTop + kBottom) / 2) +
         ") rotate(-90)\" text-anchor=\"middle\">" + htmlEscape(label) + "</text>";
}

void passLine(std::string& svg, const std::optional<double>& pass_mark) {
  if (!pass_mark) return;
  const std::string y = num(yOf(*pass_mark));
  svg += "<line class=\"pass\" x1=\"" + num(kLeft) + "\" x2=\"" + num(kRight) + "\" y1=\"" + y + "\" y2=\"" + y + "\"/>";
  svg += "<text class=\"pass-label\" x=\"" + num(kRight - 4) + "\" y=\"" + num(yOf(*pass_mark) - 4) +
         "\" text-anchor=\"end\">pass " + num(*pass_mark, 0) + "</text>";
}

}  // namespace

std::string progressSvg(const ClassReport& report, const TaskSummary& task) {
  // The time span of this task's attempts; a single moment is widened by an hour each way.
  double t0 = 0, t1 = 0;
  bool first = true;
  for (const ClassAttempt& a : report.attempts)
    if (a.task == task.name) {
      t0 = first ? a.time_s : std::min(t0, a.time_s);
      t1 = first ? a.time_s : std::max(t1, a.time_s);
      first = false;
    }
  if (t1 - t0 < 60) {
    t0 -= 3600;
    t1 += 3600;
  }
  const double pad = 0.04 * (t1 - t0);
  t0 -= pad;
  t1 += pad;
  auto xOf = [&](double t) { return kLeft + (kRight - kLeft) * (t - t0) / (t1 - t0); };

  // A long legend makes the picture taller; the axes stay where they are.
  const double height = std::max(kHeight, kTop + 8 + 18.0 * double(task.students.size()));
  std::string svg = "<svg class=\"progress\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(kWidth, 0) + "\" height=\"" +
                    num(height, 0) + "\" viewBox=\"0 0 " + num(kWidth, 0) + " " + num(height, 0) +
                    "\" role=\"img\" aria-label=\"" + htmlEscape("scores over time: " + task.title) + "\">";
  scoreAxis(svg, "score");
  // Time ticks: dates when a step is a day or more, or when the span crosses midnight.
  const double step = tickStep(t1 - t0);
  const bool one_day = timeText(t0, TimeShown::Day) == timeText(t1, TimeShown::Day);
  const TimeShown shown = step >= 86400 ? TimeShown::MonthDay : one_day ? TimeShown::Clock : TimeShown::MonthDayClock;
  for (double t = std::ceil(t0 / step) * step; t <= t1; t += step) {
    const std::string x = num(xOf(t));
    svg += "<line class=\"tickmark\" x1=\"" + x + "\" x2=\"" + x + "\" y1=\"" + num(kBottom) + "\" y2=\"" + num(kBottom + 5) + "\"/>";
    svg += "<text class=\"tick\" x=\"" + x + "\" y=\"" + num(kBottom + 18) + "\" text-anchor=\"middle\">" + timeText(t, shown) + "</text>";
  }
  svg += "<line class=\"axis\" x1=\"" + num(kLeft) + "\" x2=\"" + num(kRight) + "\" y1=\"" + num(kBottom) + "\" y2=\"" + num(kBottom) + "\"/>";
  svg += "<line class=\"axis\" x1=\"" + num(kLeft) + "\" x2=\"" + num(kLeft) + "\" y1=\"" + num(kTop) + "\" y2=\"" + num(kBottom) + "\"/>";
  const std::string day = one_day ? timeText(t0, TimeShown::Day) + ", " : "";
  svg += "<text class=\"axis-label\" x=\"" + num((kLeft + kRight) / 2) + "\" y=\"" + num(kHeight - 8) +
         "\" text-anchor=\"middle\">time (" + day + "UTC)</text>";
  passLine(svg, task.pass_mark);

  // One line and legend entry per student; every attempt a dot with its score as a tooltip.
  for (size_t s = 0; s < report.students.size(); ++s) {
    const StudentSummary& student = report.students[s];
    const std::vector<size_t> mine = attemptsOf(report, student.id, task.name);
    if (mine.empty()) continue;
    const std::string colour = studentColour(s);
    const std::string dash = s >= 10 ? " stroke-dasharray=\"6,3\"" : "";
    std::string points;
    for (size_t i : mine) points += num(xOf(report.attempts[i].time_s)) + "," + num(yOf(report.attempts[i].score)) + " ";
    svg += "<polyline class=\"student-line\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"2.5\"" + dash + " points=\"" +
           points + "\"/>";
    for (size_t i : mine) {
      const ClassAttempt& a = report.attempts[i];
      svg += "<circle cx=\"" + num(xOf(a.time_s)) + "\" cy=\"" + num(yOf(a.score)) + "\" r=\"4\" fill=\"" + colour + "\"><title>" +
             htmlEscape(isolated(student.name) + ": " + num(a.score) + " on " + utcText(a.time_s) + (a.guided ? ", guided" : "")) +
             "</title></circle>";
    }
    const size_t row = size_t(std::find(task.students.begin(), task.students.end(), student.id) - task.students.begin());
    const double ly = kTop + 8 + 18.0 * double(row);
    svg += "<line x1=\"" + num(kRight + 16) + "\" x2=\"" + num(kRight + 40) + "\" y1=\"" + num(ly) + "\" y2=\"" + num(ly) +
           "\" stroke=\"" + colour + "\" stroke-width=\"2.5\"" + dash + "/>";
    svg += "<text class=\"legend\" x=\"" + num(kRight + 46) + "\" y=\"" + num(ly) + "\" dominant-baseline=\"middle\">" +
           htmlEscape(isolated(student.name)) + "</text>";
  }
  svg += "</svg>";
  return svg;
}

// ---- 3. the histogram -----------------------------------------------------------------------------

std::string histogramSvg(const TaskSummary& task) {
  constexpr double w = 560, h = 240, left = 50, right = 540, top = 20, bottom = 200;
  const int most = std::max(1, *std::max_element(task.bins.begin(), task.bins.end()));
  auto xOf = [&](double score) { return left + (right - left) * score / 100.0; };
  auto yOf = [&](double count) { return bottom - (bottom - top) * count / most; };
  std::string svg = "<svg class=\"histogram\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(w, 0) + "\" height=\"" + num(h, 0) +
                    "\" viewBox=\"0 0 " + num(w, 0) + " " + num(h, 0) + "\" role=\"img\" aria-label=\"" +
                    htmlEscape("score distribution: " + task.title) + "\">";
  // Count ticks: whole numbers, at most five.
  const int step = std::max(1, int(std::ceil(most / 5.0)));
  for (int c = 0; c <= most; c += step) {
    const std::string y = num(yOf(c));
    svg += "<line class=\"grid\" x1=\"" + num(left) + "\" x2=\"" + num(right) + "\" y1=\"" + y + "\" y2=\"" + y + "\"/>";
    svg += "<text class=\"tick\" x=\"" + num(left - 6) + "\" y=\"" + y + "\" text-anchor=\"end\" dominant-baseline=\"middle\">" +
           std::to_string(c) + "</text>";
  }
  for (int b = 0; b < kScoreBins; ++b) {
    const int count = task.bins[size_t(b)];
    const double x = xOf(b * 10.0) + 2, bw = xOf(10.0) - xOf(0.0) - 4;
    if (count > 0) {
      svg += "<rect class=\"bar\" x=\"" + num(x) + "\" y=\"" + num(yOf(count)) + "\" width=\"" + num(bw) + "\" height=\"" +
             num(bottom - yOf(count)) + "\"><title>" + std::to_string(count) + " attempts scored " +
             std::to_string(b * 10) + (b == kScoreBins - 1 ? "-100" : "-" + std::to_string(b * 10 + 10)) + "</title></rect>";
      svg += "<text class=\"count\" x=\"" + num(x + bw / 2) + "\" y=\"" + num(yOf(count) - 4) + "\" text-anchor=\"middle\">" +
             std::to_string(count) + "</text>";
    }
  }
  for (int s = 0; s <= 100; s += 10)
    svg += "<text class=\"tick\" x=\"" + num(xOf(s)) + "\" y=\"" + num(bottom + 16) + "\" text-anchor=\"middle\">" + std::to_string(s) + "</text>";
  svg += "<line class=\"axis\" x1=\"" + num(left) + "\" x2=\"" + num(right) + "\" y1=\"" + num(bottom) + "\" y2=\"" + num(bottom) + "\"/>";
  svg += "<line class=\"axis\" x1=\"" + num(left) + "\" x2=\"" + num(left) + "\" y1=\"" + num(top) + "\" y2=\"" + num(bottom) + "\"/>";
  svg += "<text class=\"axis-label\" x=\"" + num((left + right) / 2) + "\" y=\"" + num(h - 6) + "\" text-anchor=\"middle\">score</text>";
  svg += "<text class=\"axis-label\" transform=\"translate(14," + num((top + bottom) / 2) + ") rotate(-90)\" text-anchor=\"middle\">attempts</text>";
  if (task.pass_mark) {
    const std::string x = num(xOf(std::clamp(*task.pass_mark, 0.0, 100.0)));
    svg += "<line class=\"pass\" x1=\"" + x + "\" x2=\"" + x + "\" y1=\"" + num(top) + "\" y2=\"" + num(bottom) + "\"/>";
    svg += "<text class=\"pass-label\" x=\"" + x + "\" y=\"" + num(top - 6) + "\" text-anchor=\"middle\">pass " +
           num(*task.pass_mark, 0) + "</text>";
  }
  svg += "</svg>";
  return svg;
}

// ---- 4. the points lost ---------------------------------------------------------------------------

namespace {

// "pulp_exposure" -> "pulp exposure": the report's keys, read as words.
std::string partLabel(const std::string& name) {
  std::string label = name;
  std::replace(label.begin(), label.end(), '_', ' ');
  return label;
}

// The colour class of a share lost: none lost, then four steps to all of it.
const char* lossClass(double share) {
  if (share < 1e-3) return "kept";
  if (share <= 0.2) return "lost-1";
  if (share <= 0.5) return "lost-2";
  if (share <= 0.8) return "lost-3";
  return "lost-4";
}

// One part as words: "undercut 5.0 of 25", "healthy 0.6 off", "pulp exposure: total capped at 50".
std::string partText(const AttemptPart& p) {
  const std::string label = partLabel(p.name);
  if (p.cap) return label + ": total capped at " + num(*p.cap);
  if (!p.points) return label + " not scored";
  if (p.deduction) return label + " " + num(*p.points) + " off";
  std::string text = label + " " + num(*p.points) + " of " + num(*p.max, *p.max == std::round(*p.max) ? 0 : 1);
  // A part earned in proportion to the work done says how much of it counted: a token cut earns little.
  if (p.earned_share && *p.earned_share < 1.0) text += " (" + num(100.0 * *p.earned_share, 0) + " % earned)";
  return text;
}

}  // namespace

std::string partsHtml(const ClassAttempt& a) {
  if (a.parts.empty()) return kNone;
  std::string marks, all;
  struct Loss { std::string text; double points; };
  std::vector<Loss> losses;
  std::vector<std::string> unscored;
  for (const AttemptPart& p : a.parts) {
    const std::optional<double> share = lostShare(p, a.total_max);
    const std::optional<double> lost = pointsLost(p);
    const std::string state = p.cap ? "lost capped" : !share ? "unscored" : std::string(*share < 1e-3 ? "" : "lost ") + lossClass(*share);
    const std::string text = partText(p);
    all += (all.empty() ? "" : "; ") + text;
    marks += "<span class=\"part " + state + (p.deduction ? " deduction" : "") + "\" data-part=\"" + htmlEscape(p.name) +
             "\" data-lost=\"" + (lost ? num(*lost, 2) : std::string(p.cap ? "cap" : "")) + "\" title=\"" + htmlEscape(text) + "\"></span>";
    if (p.cap) losses.push_back({partLabel(p.name) + " capped at " + num(*p.cap), 1e9});
    else if (!share) unscored.push_back(partLabel(p.name));
    else if (lost && *lost >= 0.05) losses.push_back({partLabel(p.name) + " \u2212" + num(*lost), *lost});
  }
  // The words say why, the biggest loss first; the marks keep the report's order.
  std::stable_sort(losses.begin(), losses.end(), [](const Loss& x, const Loss& y) { return x.points > y.points; });
  std::string why;
  for (const Loss& l : losses) why += (why.empty() ? "" : ", ") + l.text;
  if (why.empty()) why = "none lost";
  if (!unscored.empty()) {
    why += "; not scored:";
    for (size_t i = 0; i < unscored.size(); ++i) why += (i ? ", " : " ") + unscored[i];
  }
  return "<span class=\"heat\" role=\"img\" aria-label=\"" + htmlEscape("parts: " + all) + "\">" + marks +
         "</span><span class=\"why\">" + htmlEscape(why) + "</span>";
}

// ---- 5. the page ----------------------------------------------------------------------------------

namespace {

constexpr const char* kStyle = R"(
body { font: 15px/1.4 system-ui, sans-serif; color: #222; background: #fff; margin: 24px; max-width: 1400px; }
h1 { margin-bottom: 4px; } h2 { border-bottom: 1px solid #ccc; margin-top: 32px; }
table { border-collapse: collapse; margin: 8px 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: left; overflow-wrap: anywhere; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.flagged td { background: #fdecea; }
.task { margin: 12px 0 24px; }
svg text { font: 12px system-ui, sans-serif; fill: #333; }
svg .grid { stroke: #e4e4e4; } svg .axis, svg .tickmark { stroke: #444; }
svg .pass { stroke: #c0392b; stroke-width: 1.5; stroke-dasharray: 6,4; } svg .pass-label { fill: #c0392b; }
svg .bar { fill: #4a7fb5; } svg .count { font-weight: bold; }
.pictures { display: flex; flex-wrap: wrap; gap: 16px; }
figure { margin: 0; border: 1px solid #ccc; padding: 6px; width: 360px; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 13px; margin-top: 4px; overflow-wrap: anywhere; }
.nopic { color: #888; font-style: italic; padding: 40px 0; text-align: center; }
.samepic, .filepic { display: block; padding: 40px 0; text-align: center; overflow-wrap: anywhere; }
.heat { display: inline-flex; gap: 2px; vertical-align: middle; margin-right: 6px; }
.part { display: inline-block; width: 14px; height: 14px; border-radius: 2px; box-sizing: border-box; }
.part.deduction { border-radius: 7px; }
.part.kept { background: #2e9d57; } .part.lost-1 { background: #f2c94c; } .part.lost-2 { background: #ee9a3a; }
.part.lost-3 { background: #dd5a2b; } .part.lost-4 { background: #b3241c; } .part.capped { background: #5e1410; }
.part.unscored { background: #fff; border: 1px dashed #999; }
.why { font-size: 13px; color: #444; }
td.parts { min-width: 240px; } td.date, td.num { white-space: nowrap; }
td.from { font-size: 13px; color: #555; overflow-wrap: anywhere; }
.key .part { vertical-align: -2px; margin: 0 3px 0 8px; }
)";

std::string cell(const std::string& text, bool number = false) {
  return std::string(number ? "<td class=\"num\">" : "<td>") + htmlEscape(text) + "</td>";
}

// A cell holding a name or title from a file: shortened and bidi-isolated.
std::string nameCell(const std::string& text) { return "<td>" + bdi(text) + "</td>"; }

// A cell of a given class ("date", "from").
std::string cellOf(const char* css_class, const std::string& text) {
  return std::string("<td class=\"") + css_class + "\">" + htmlEscape(text) + "</td>";
}

std::string durationText(const std::optional<double>& s) {
  if (!s) return kNone;
  const int total = int(std::lround(*s));
  char text[32];
  std::snprintf(text, sizeof text, "%d:%02d", total / 60, total % 60);
  return text;
}

std::string studentName(const ClassReport& r, const std::string& id) {
  for (const StudentSummary& s : r.students)
    if (s.id == id) return s.name;
  return id;
}

std::string agreementText(const std::optional<AttemptAgreement>& a) {
  if (!a) return kNone;
  return num(a->within_percent) + " % within \u00b1" + num(a->band_mm, 2) + " mm";
}

void studentsSection(std::string& html, const ClassReport& r) {
  html += "<h2>Students</h2><table class=\"students\"><tr><th>student</th><th>id</th><th>attempts</th><th>tasks</th></tr>";
  for (const StudentSummary& s : r.students)
    html += "<tr>" + nameCell(s.name) + nameCell(s.id) + cell(std::to_string(s.attempts), true) + cell(std::to_string(s.tasks), true) + "</tr>";
  html += "</table>";
}

void tasksSection(std::string& html, const ClassReport& r) {
  html += "<h2>Progress and scores by task</h2>";
  for (const TaskSummary& t : r.tasks) {
    html += "<div class=\"task\"><h3>" + bdi(t.title) + " <small>(" + bdi(t.name) + ")</small></h3>";
    html += "<p>" + std::to_string(t.attempts) + " attempts by " + std::to_string(t.students.size()) + " students; score min " +
            num(t.min) + ", median " + num(t.median) + ", max " + num(t.max) +
            (t.pass_mark ? "; pass mark " + num(*t.pass_mark, 0) : "; no pass mark") + ".</p>";
    html += progressSvg(r, t);
    html += histogramSvg(t);
    html += "</div>";
  }
}

void flaggedSection(std::string& html, const ClassReport& r) {
  html += "<h2>Attempts to look at</h2>";
  if (r.flags.empty()) {
    html += "<p>No attempt exposed the pulp, damaged an adjacent tooth, failed or fell below a pass mark.</p>";
    return;
  }
  std::string opened;  // the kinds whose students are to open the pulp
  for (const TaskKindRow& kind : kTaskKindTable)
    if (kind.pulp == PulpRule::MustOpen) opened += (opened.empty() ? "" : " or ") + kindWithArticle(kind);
  html += "<p>Attempts that exposed the pulp (not a fault in " + opened +
          "), damaged an adjacent tooth, failed, or fell below the pass mark.</p>";
  html += "<table class=\"flagged\"><tr><th>student</th><th>task</th><th>date (UTC)</th><th>score</th><th>why</th>"
          "<th>points lost</th><th>from</th></tr>";
  for (const FlaggedAttempt& f : r.flags) {
    const ClassAttempt& a = r.attempts[f.attempt];
    std::string why;
    for (const std::string& reason : f.reasons) why += (why.empty() ? "" : ", ") + reason;
    html += "<tr class=\"flagged\">" + nameCell(studentName(r, a.student)) + nameCell(a.task_title) + cellOf("date", utcText(a.time_s)) +
            cell(num(a.score), true) + cell(why) + "<td class=\"parts\">" + partsHtml(a) + "</td>" + cellOf("from", a.source) + "</tr>";
  }
  html += "</table>";
}

void attemptsSection(std::string& html, const ClassReport& r) {
  html += "<h2>All attempts</h2>";
  html += "<p class=\"key\">Points lost: one mark per part of the score, in the report's order, squares for the parts "
          "earned and dots for the deductions:<span class=\"part kept\"></span>none lost<span class=\"part lost-1\"></span>"
          "up to a fifth<span class=\"part lost-2\"></span>up to half<span class=\"part lost-3\"></span>up to four fifths"
          "<span class=\"part lost-4\"></span>more<span class=\"part capped\"></span>the total capped"
          "<span class=\"part unscored\"></span>not scored. A deduction counts against the whole score. "
          "Hover a mark for its points. Surface agreement: the share of the ideal cavity's surface the student's "
          "matches within the band.</p>";
  html += "<table class=\"attempts\"><tr><th>date (UTC)</th><th>student</th><th>task</th><th>score</th>"
          "<th>points lost</th><th>time taken</th><th>surface agreement</th><th>result</th><th>from</th></tr>";
  for (const ClassAttempt& a : r.attempts)
    html += "<tr>" + cellOf("date", utcText(a.time_s)) + nameCell(studentName(r, a.student)) + nameCell(a.task_title) +
            cell(num(a.score), true) +
            "<td class=\"parts\">" + partsHtml(a) + "</td>" + cell(durationText(a.duration_s), true) +
            cell(agreementText(a.agreement), true) + cell(a.guided ? a.verb + " (guided)" : a.verb) + cellOf("from", a.source) + "</tr>";
  html += "</table>";
}

// Where a picture past the cap is: a file: URL of its absolute path, every byte but the unreserved
// ones and '/' percent-encoded, so that no path can end the attribute or name another scheme.
std::string fileUrl(const std::string& path) {
  std::error_code ec;
  const std::string abs = std::filesystem::absolute(path, ec).lexically_normal().string();
  return "file://" + percentEncoded(ec ? path : abs, "/");
}

void picturesSection(std::string& html, const ClassReport& r, const ReportPictures& pictures) {
  html += "<h2>Score pictures</h2><p>Red: over-cut, or healthy tissue cut outside the allowed zone; blue: under-cut.</p>"
          "<div class=\"pictures\">";
  std::map<size_t, std::string> shown;  // a picture's index in pngs -> the caption of the attempt that embedded it
  for (const ClassAttempt& a : r.attempts) {
    // The name and the title isolated, so that neither can reorder the score after them.
    const std::string rest = " \u2014 " + num(a.score) + " \u2014 " + utcText(a.time_s) + (a.guided ? " \u2014 guided" : "");
    const std::string name = studentName(r, a.student);
    const std::string caption_text = isolated(name) + " \u2014 " + isolated(a.task_title) + rest;
    const std::string caption_html = bdi(name) + " \u2014 " + bdi(a.task_title) + htmlEscape(rest);
    html += "<figure>";
    const auto it = a.picture.empty() ? pictures.embedded.end() : pictures.embedded.find(a.picture);
    if (it != pictures.embedded.end()) {
      const std::string id = "pic-" + std::to_string(it->second);
      if (const auto first = shown.find(it->second); first != shown.end()) {
        // Embedded once already: a link to it keeps the page's size to one copy.
        html += "<a class=\"samepic\" href=\"#" + id + "\">the same picture as " + first->second + "</a>";
      } else {
        shown.emplace(it->second, caption_html);
        html += "<img alt=\"" + htmlEscape("score picture: " + caption_text) + "\" id=\"" + id + "\" src=\"data:image/png;base64," +
                base64(pictures.pngs[it->second]) + "\">";
      }
    } else if (!a.picture.empty() && pictures.linked.count(a.picture)) {
      html += "<a class=\"filepic\" href=\"" + htmlEscape(fileUrl(a.picture)) + "\">" + htmlEscape(a.picture) + "</a>";
    } else {
      html += "<div class=\"nopic\">no picture</div>";
    }
    html += "<figcaption>" + caption_html + "</figcaption></figure>";
  }
  html += "</div>";
}

}  // namespace

bool ReportPictures::add(const std::string& path, std::vector<uint8_t> bytes) {
  for (size_t i = 0; i < pngs.size(); ++i)
    if (pngs[i] == bytes) {
      embedded[path] = i;
      return false;
    }
  embedded[path] = pngs.size();
  pngs.push_back(std::move(bytes));
  return true;
}

std::string classReportHtml(const ClassReport& r, const ReportPictures& pictures) {
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                     "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; style-src 'unsafe-inline'\">"
                     "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
                     "<title>dentsim class report</title><style>";
  html += kStyle;
  html += "</style></head><body><h1>Class report</h1><p class=\"summary\">" + std::to_string(r.attempts.size()) + " attempts by " +
          std::to_string(r.students.size()) + " students at " + std::to_string(r.tasks.size()) + " tasks";
  if (!r.attempts.empty()) html += ", " + utcText(r.first_s) + " to " + utcText(r.last_s) + " UTC";
  html += ".</p>\n";
  studentsSection(html, r);
  tasksSection(html, r);
  flaggedSection(html, r);
  attemptsSection(html, r);
  picturesSection(html, r, pictures);
  html += "\n</body></html>\n";
  return html;
}

}  // namespace dentsim
