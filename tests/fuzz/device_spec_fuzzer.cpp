// libFuzzer entry for the device names on the command line: --pedal specs and --drill/--mirror pen names are refused on one line that names them, and accepted layouts decode any report.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "devices/device_registry.h"
#include "devices/hid_pedal.h"

namespace {

using dentsim::devices::PedalInput;
using dentsim::devices::PedalLayout;

void require(bool holds) {
  if (!holds) std::abort();
}

bool printable(const std::string& text) {
  for (char c : text)
    if (uint8_t(c) < 0x20 || uint8_t(c) == 0x7f) return false;
  return true;
}

// One line; where the input has no control bytes to escape, it starts with the input's name.
void requireOneLine(const std::string& message, const std::string& input, const std::string& name) {
  require(!message.empty());
  require(message.find('\n') == std::string::npos && message.find('\r') == std::string::npos);
  if (printable(input)) require(message.rfind(name + ": ", 0) == 0);
}

size_t bytesNeeded(const PedalLayout& l) {
  switch (l.input) {
    case PedalInput::Button: return size_t(l.byte) + 1;
    case PedalInput::Axis: return (size_t(l.byte) * 8 + size_t(l.bit) + size_t(l.bits) + 7) / 8;
    case PedalInput::Key: return l.report_id >= 0 ? 9 : 8;
  }
  return 0;
}

void checkSpec(const std::string& text) {
  const auto r = dentsim::devices::parseHidPedalSpec(text);
  const std::string name = "hid:" + (text.rfind("hid:", 0) == 0 ? text.substr(4) : text);
  if (!r.ok()) {
    requireOneLine(r.message(), text, name);
    return;
  }
  require(r->text == name);
  if (r->dead_band) require(*r->dead_band >= 0.0 && *r->dead_band < 0.5);
  if (r->report_id) require(*r->report_id >= 0 && *r->report_id <= 255);
  if (!r->layout) return;
  // The layout with the options applied, as the pedal uses it, on reports of every length up to one
  // past the field, all ones (the report id in front) and all zeros.
  PedalLayout l = *r->layout;
  if (r->invert) l.invert = *r->invert;
  if (r->dead_band) l.dead_band = *r->dead_band;
  if (r->report_id) l.report_id = *r->report_id;
  require(l.byte >= 0 && l.byte <= 255);
  const size_t need = bytesNeeded(l);
  for (size_t n = 0; n <= need + 1; ++n) {
    for (uint8_t fill : {uint8_t{0x00}, uint8_t{0xFF}}) {
      std::vector<uint8_t> report(n, fill);
      if (!report.empty() && l.report_id >= 0) report[0] = uint8_t(l.report_id);
      const std::optional<double> v = dentsim::devices::decodePedalReport(l, report);
      require(v.has_value() == (n >= need));
      if (v) require(std::isfinite(*v) && *v >= 0.0 && *v <= 1.0);
    }
  }
}

void checkPenName(const std::string& text) {
  const auto r = dentsim::devices::parsePenName(text);
  if (!r.ok()) {
    requireOneLine(r.message(), text, "pen '" + text + "'");
    return;
  }
  require(r->text == text && !r->backend.empty());
  require(r->backend == text.substr(0, text.find(':')));
  if (r->backend == "falcon") require(!r->arg.empty());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  checkSpec(text);
  checkPenName(text);
  return 0;
}
