// The class report as one self-contained HTML page: inline CSS, inline SVG plots, score pictures as data: URIs (each once), no script and no request.
//
// The page's Content-Security-Policy allows only inline styles and data: images, so a browser
// refuses any request the page might make. Every text that came from a file (student names, task
// titles, paths) goes through htmlEscape.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "eval/class_report.h"

namespace dentsim {

// The score pictures the page shows, by the path an attempt names. Each distinct picture's bytes go
// into the page once: the first attempt showing it embeds it, later ones link to that one, so a
// class's outbox naming one picture 400 times costs one picture, not 400. A picture in `linked`
// (past the page's cap on embedded bytes) is a link to its file; one in neither shows "no picture".
struct ReportPictures {
  std::vector<std::vector<uint8_t>> pngs;   // each distinct picture's PNG bytes
  std::map<std::string, size_t> embedded;   // a picture's path -> its bytes' index in pngs
  std::set<std::string> linked;             // pictures shown as a link to the file, not embedded

  // Adds the bytes of the picture at `path`; bytes equal to an earlier picture's share its entry.
  // Returns whether they were new (and so add to the page's size).
  bool add(const std::string& path, std::vector<uint8_t> bytes);
  // How many pictures the page embeds and links.
  size_t count() const { return embedded.size() + linked.size(); }
};

// The whole page.
std::string classReportHtml(const ClassReport& report, const ReportPictures& pictures);

// ---- the parts, for tests ------------------------------------------------------------------------

// Text made safe inside HTML and SVG elements and quoted attributes: & < > " ' as entities.
std::string htmlEscape(std::string_view text);
// Standard base64 with padding (RFC 4648), for data: URIs.
std::string base64(std::span<const uint8_t> bytes);
// "2026-11-27 08:15" in UTC.
std::string utcText(double time_s);
// One task's progress plot: score (0..100) against time, one line per student, the pass mark dashed.
std::string progressSvg(const ClassReport& report, const TaskSummary& task);
// One task's histogram of scores in ten bins, each bar with its count, the pass mark dashed.
std::string histogramSvg(const TaskSummary& task);
// One attempt's points lost: a mark per part (class "part", then "kept", "lost lost-1".."lost lost-4",
// "lost capped" or "unscored"; data-part the report's key, data-lost the points lost), the parts in
// words for screen readers (aria-label), and the losses in words, biggest first; an em dash when
// the attempt names no parts.
std::string partsHtml(const ClassAttempt& attempt);
// The i-th student's line colour ("#1f77b4"); colours repeat after ten, with a dash from the 11th.
std::string studentColour(size_t i);

}  // namespace dentsim
