// A hand-built DICOM slice (explicit VR little endian, 2 x 2 pixels) whose header holds sequences nested `depth` deep, for the readers' nesting limit.
#pragma once

#include <cstdint>
#include <string>

namespace dentsim::test {

namespace nested_dicom {
inline void le16(std::string& s, uint16_t v) {
  s += char(v & 0xff);
  s += char(v >> 8);
}
inline void le32(std::string& s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s += char((v >> (8 * i)) & 0xff);
}
// One element with a defined length; OB, OW, SQ and UN take the long form of explicit VR.
inline void element(std::string& s, uint16_t group, uint16_t tag, const std::string& vr, std::string value) {
  if (value.size() % 2) value += (vr == "UI" ? '\0' : ' ');
  le16(s, group);
  le16(s, tag);
  s += vr;
  if (vr == "OB" || vr == "OW" || vr == "SQ" || vr == "UN") {
    le16(s, 0);
    le32(s, uint32_t(value.size()));
  } else {
    le16(s, uint16_t(value.size()));
  }
  s += value;
}
inline std::string us(uint16_t v) {
  std::string s;
  le16(s, v);
  return s;
}
}  // namespace nested_dicom

// Referenced Series Sequence (0008,1115) inside its own only item, `depth` times, every sequence
// and item of undefined length (36 bytes a level: 100 levels make the 3.6 kB file of issue 40).
inline std::string nestedSequenceSlice(int depth) {
  using namespace nested_dicom;
  std::string meta;
  element(meta, 0x0002, 0x0001, "OB", std::string("\0\1", 2));
  element(meta, 0x0002, 0x0002, "UI", "1.2.840.10008.5.1.4.1.1.2");  // CT Image Storage
  element(meta, 0x0002, 0x0003, "UI", "1.2.3.4");
  element(meta, 0x0002, 0x0010, "UI", "1.2.840.10008.1.2.1");  // explicit VR little endian
  std::string f(128, '\0');
  f += "DICM";
  std::string meta_length;
  le32(meta_length, uint32_t(meta.size()));
  element(f, 0x0002, 0x0000, "UL", meta_length);
  f += meta;
  element(f, 0x0008, 0x0016, "UI", "1.2.840.10008.5.1.4.1.1.2");
  element(f, 0x0008, 0x0060, "CS", "CT");
  for (int d = 0; d < depth; ++d) {
    le16(f, 0x0008), le16(f, 0x1115), f += "SQ", le16(f, 0), le32(f, 0xffffffffu);  // sequence
    le16(f, 0xfffe), le16(f, 0xe000), le32(f, 0xffffffffu);                        // its item
  }
  for (int d = 0; d < depth; ++d) {
    le16(f, 0xfffe), le16(f, 0xe00d), le32(f, 0);  // item delimiter
    le16(f, 0xfffe), le16(f, 0xe0dd), le32(f, 0);  // sequence delimiter
  }
  element(f, 0x0020, 0x000e, "UI", "1.2.3.5");
  element(f, 0x0028, 0x0002, "US", us(1));
  element(f, 0x0028, 0x0004, "CS", "MONOCHROME2");
  element(f, 0x0028, 0x0010, "US", us(2));
  element(f, 0x0028, 0x0011, "US", us(2));
  element(f, 0x0028, 0x0100, "US", us(16));
  element(f, 0x0028, 0x0101, "US", us(16));
  element(f, 0x0028, 0x0102, "US", us(15));
  element(f, 0x0028, 0x0103, "US", us(1));
  element(f, 0x7fe0, 0x0010, "OW", std::string(8, '\0'));
  return f;
}

}  // namespace dentsim::test
