// The Falcon's packet codec and stream reassembly: pure functions, no USB.
#include "devices/falcon_protocol.h"

#include <cassert>
#include <cstring>

namespace dentsim::devices::falcon {

namespace {

constexpr uint8_t kStart = '<';
constexpr uint8_t kEnd = '>';
constexpr uint8_t kNibbleBase = 'A';
constexpr size_t kStatusByte = 13;
constexpr size_t kSpareByte = 14;

// A motor word or encoder count as four nibble bytes, least significant nibble first.
void putWord(int16_t word, uint8_t* at) {
  const auto bits = static_cast<uint16_t>(word);
  for (int k = 0; k < 4; ++k) at[k] = static_cast<uint8_t>(kNibbleBase + ((bits >> (4 * k)) & 0xF));
}

bool isNibble(uint8_t b) { return b >= kNibbleBase && b < kNibbleBase + 16; }

int16_t getWord(const uint8_t* at) {
  uint16_t bits = 0;
  for (int k = 0; k < 4; ++k) bits = static_cast<uint16_t>(bits | ((at[k] - kNibbleBase) & 0xF) << (4 * k));
  return static_cast<int16_t>(bits);
}

}  // namespace

bool isLoaderHelloReply(const uint8_t* reply, size_t size) {
  const size_t n = kLoaderHelloReply.size();
  if (size == n) return std::memcmp(reply, kLoaderHelloReply.data(), n) == 0;
  if (size == n + 1) return reply[0] == 0x00 && std::memcmp(reply + 1, kLoaderHelloReply.data(), n) == 0;
  return false;
}

Packet encodeCommand(const Command& c) {
  Packet p{};
  p[0] = kStart;
  for (size_t i = 0; i < 3; ++i) putWord(c.motor[i], &p[1 + 4 * i]);
  const uint8_t status = static_cast<uint8_t>((c.leds & (kLedGreen | kLedBlue | kLedRed)) | (c.homing ? kHomingMode : 0));
  p[kStatusByte] = static_cast<uint8_t>(kNibbleBase + status);
  p[kSpareByte] = kNibbleBase;
  p[15] = kEnd;
  return p;
}

bool decodeStatus(const uint8_t* packet, Reply* out) {
  assert(packet && out);
  if (packet[0] != kStart || packet[15] != kEnd) return false;
  for (size_t i = 1; i <= 12; ++i)
    if (!isNibble(packet[i])) return false;
  // The status byte carries 7 bits (homing 4-6, grip 0-3) above 'A'.
  if (packet[kStatusByte] < kNibbleBase || packet[kStatusByte] >= kNibbleBase + 0x80) return false;
  Reply s;
  for (size_t i = 0; i < 3; ++i) s.encoder[i] = getWord(&packet[1 + 4 * i]);
  const auto status = static_cast<uint8_t>(packet[kStatusByte] - kNibbleBase);
  s.homed = static_cast<uint8_t>((status >> 4) & kAllAxesHomed);
  s.grip = static_cast<uint8_t>(status & 0xF);
  *out = s;
  return true;
}

size_t stripModemStatus(const uint8_t* transfer, size_t size, uint8_t* out) {
  size_t written = 0;
  for (size_t at = 0; at < size; at += kUsbPacketSize) {
    const size_t packet = size - at < kUsbPacketSize ? size - at : kUsbPacketSize;
    if (packet <= kModemStatusSize) continue;
    std::memcpy(out + written, transfer + at + kModemStatusSize, packet - kModemStatusSize);
    written += packet - kModemStatusSize;
  }
  return written;
}

int PacketAssembler::feed(const uint8_t* bytes, size_t size, Reply* latest) {
  int decoded = 0;
  for (size_t i = 0; i < size; ++i) {
    const uint8_t b = bytes[i];
    if (b == kStart && fill_ > 0) {  // a new packet before the last one ended: drop the fragment
      dropped_ += fill_;
      fill_ = 0;
    }
    if (fill_ == 0 && b != kStart) {  // between packets only a '<' may come
      ++dropped_;
      continue;
    }
    buffer_[fill_++] = b;
    if (fill_ < kPacketSize) continue;
    Reply s;
    if (decodeStatus(buffer_.data(), &s)) {
      *latest = s;
      ++decoded;
    } else {
      dropped_ += kPacketSize;
    }
    fill_ = 0;
  }
  return decoded;
}

}  // namespace dentsim::devices::falcon
