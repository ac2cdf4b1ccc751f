// libFuzzer entry for the HID report descriptor walk: a layout it finds must address a field hidapi can hand over, and decode any report to [0, 1] or to nothing.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>
#include <vector>

#include "devices/hid_pedal.h"

namespace {

using dentsim::devices::PedalInput;
using dentsim::devices::PedalLayout;

void require(bool holds) {
  if (!holds) std::abort();
}

// The bytes a report needs to hold the field the layout names.
size_t bytesNeeded(const PedalLayout& l) {
  if (l.input == PedalInput::Axis) return (size_t(l.byte) * 8 + size_t(l.bit) + size_t(l.bits) + 7) / 8;
  return size_t(l.byte) + 1;
}

// nullopt exactly when the report carries another id or is too short; otherwise a position in
// [0, 1]. The copy is exactly the report's size, so ASan sees a read past its end.
void decodeChecked(const PedalLayout& l, const std::vector<uint8_t>& bytes) {
  const std::vector<uint8_t> report(bytes);
  const std::optional<double> v = dentsim::devices::decodePedalReport(l, report);
  const bool for_pedal = l.report_id < 0 || (!report.empty() && report[0] == l.report_id);
  require(v.has_value() == (for_pedal && report.size() >= bytesNeeded(l)));
  if (v) require(std::isfinite(*v) && *v >= 0.0 && *v <= 1.0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::optional<PedalLayout> found = dentsim::devices::layoutFromReportDescriptor(std::span<const uint8_t>(data, size));
  if (!found) return 0;
  const PedalLayout& l = *found;
  require(l.report_id >= -1 && l.report_id <= 255);
  require(l.byte >= (l.report_id >= 0 ? 1 : 0) && l.byte <= 255);  // a numbered report's id is byte 0
  if (l.input == PedalInput::Button) {
    require(l.button_mask != 0 && (l.button_mask & (l.button_mask - 1)) == 0);
  } else {
    require(l.input == PedalInput::Axis);
    require(l.bit >= 0 && l.bit <= 7 && l.bits >= 1 && l.bits <= 32 && l.raw_min != l.raw_max);
  }
  // The input's own bytes as a report, then all-zero and all-one reports one byte short of the
  // field, just long enough, and longer, each with the layout's report id in front.
  decodeChecked(l, std::vector<uint8_t>(data, data + size));
  const size_t need = bytesNeeded(l);
  for (size_t n : {need - 1, need, need + 3}) {
    for (uint8_t fill : {uint8_t{0x00}, uint8_t{0xFF}, uint8_t{0x55}}) {
      std::vector<uint8_t> report(n, fill);
      if (!report.empty() && l.report_id >= 0) report[0] = uint8_t(l.report_id);
      decodeChecked(l, report);
    }
  }
  return 0;
}
