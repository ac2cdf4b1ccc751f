// Forging one header value in a DICOM file that dentsim wrote (explicit VR little endian), for the readers' checks of made-up data.
#pragma once

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

namespace dentsim::test {

// Sets the US element (group, element) of the file at `path` to `value`; false when the file has no
// such element. The element is found by its tag, VR and length (8 bytes: "gggg eeee US 02 00"), which
// in the files writeDicomSeries makes is unique.
inline bool forgeUs(const std::string& path, uint16_t group, uint16_t element, uint16_t value) {
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string key{char(group & 0xff), char(group >> 8), char(element & 0xff), char(element >> 8), 'U', 'S', 2, 0};
  const size_t at = bytes.find(key);
  if (at == std::string::npos) return false;
  bytes[at + 8] = char(value & 0xff);
  bytes[at + 9] = char(value >> 8);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return true;
}

}  // namespace dentsim::test
