// Tests for devices/falcon_protocol.cpp: packet bytes worked out by hand from the nibble encoding, no USB.
#include "devices/falcon_protocol.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace dentsim::devices::falcon {
namespace {

std::string text(const Packet& p) { return std::string(p.begin(), p.end()); }

// A reply packet with encoders e and the status byte 'A' + (homed << 4 | grip).
std::string reply(const char* encoders12, uint8_t homed, uint8_t grip) {
  std::string s = "<";
  s += encoders12;
  s += static_cast<char>('A' + (homed << 4 | grip));
  s += "A>";
  return s;
}

TEST(FalconProtocol, ZeroCommandIsAllA) {
  // Every nibble 0 is 'A'; no LEDs, no homing.
  EXPECT_EQ(text(encodeCommand({})), "<AAAAAAAAAAAAAA>");
}

TEST(FalconProtocol, CommandNibblesLeastSignificantFirst) {
  Command c;
  c.motor = {1, -1, 0x1234};
  c.leds = kLedRed;
  c.homing = true;
  // 1 -> nibbles 1,0,0,0 = "BAAA"; -1 = 0xFFFF -> "PPPP"; 0x1234 -> 4,3,2,1 = "EDCB";
  // status 0x8 | 0x1 = 9 -> 'J'.
  EXPECT_EQ(text(encodeCommand(c)), "<BAAAPPPPEDCBJA>");
  c.leds = kLedGreen | kLedBlue;
  c.homing = false;
  c.motor = {-32768, 32767, 0};
  // 0x8000 -> 0,0,0,8 = "AAAI"; 0x7FFF -> F,F,F,7 = "PPPH"; status 0x6 -> 'G'.
  EXPECT_EQ(text(encodeCommand(c)), "<AAAIPPPHAAAAGA>");
}

TEST(FalconProtocol, DecodeStatus) {
  const std::string p = reply("BAAAPPPPEDCB", 7, 1);
  Reply s;
  ASSERT_TRUE(decodeStatus(reinterpret_cast<const uint8_t*>(p.data()), &s));
  EXPECT_EQ(s.encoder[0], 1);
  EXPECT_EQ(s.encoder[1], -1);
  EXPECT_EQ(s.encoder[2], 0x1234);
  EXPECT_EQ(s.homed, kAllAxesHomed);
  EXPECT_EQ(s.grip, 1);
  const std::string partly = reply("AAAIPPPHAAAA", 5, 0);  // motors 1 and 3 homed
  ASSERT_TRUE(decodeStatus(reinterpret_cast<const uint8_t*>(partly.data()), &s));
  EXPECT_EQ(s.encoder[0], -32768);
  EXPECT_EQ(s.encoder[1], 32767);
  EXPECT_EQ(s.homed, 5);
}

TEST(FalconProtocol, DecodeRejectsBadFraming) {
  Reply s;
  std::string p = reply("AAAAAAAAAAAA", 0, 0);
  p[15] = 'A';  // no closing '>'
  EXPECT_FALSE(decodeStatus(reinterpret_cast<const uint8_t*>(p.data()), &s));
  p = reply("AAAAAAAAAAAA", 0, 0);
  p[5] = 'Z';  // not a nibble ('A'..'P')
  EXPECT_FALSE(decodeStatus(reinterpret_cast<const uint8_t*>(p.data()), &s));
}

TEST(FalconProtocol, StripsModemStatusOfEveryUsbPacket) {
  // 130 bytes = 64 + 64 + 2: each USB packet opens with 2 status bytes, the last holds only those.
  std::vector<uint8_t> transfer(130);
  for (size_t i = 0; i < transfer.size(); ++i) transfer[i] = static_cast<uint8_t>(i);
  std::vector<uint8_t> out(130, 0xEE);
  ASSERT_EQ(stripModemStatus(transfer.data(), transfer.size(), out.data()), 124u);  // 62 + 62 + 0
  EXPECT_EQ(out[0], 2);     // first payload byte follows the two status bytes
  EXPECT_EQ(out[61], 63);   // last of the first packet
  EXPECT_EQ(out[62], 66);   // 64, 65 were the second packet's status
  EXPECT_EQ(out[123], 127);
  EXPECT_EQ(stripModemStatus(transfer.data(), 2, out.data()), 0u);  // a status-only transfer
}

TEST(FalconProtocol, AssemblerJoinsSplitPackets) {
  const std::string p = reply("BAAAAAAAAAAA", 7, 0);
  PacketAssembler a;
  Reply s;
  const auto* bytes = reinterpret_cast<const uint8_t*>(p.data());
  EXPECT_EQ(a.feed(bytes, 5, &s), 0);
  EXPECT_EQ(a.feed(bytes + 5, 11, &s), 1);
  EXPECT_EQ(s.encoder[0], 1);
  EXPECT_EQ(a.droppedBytes(), 0u);
}

TEST(FalconProtocol, AssemblerResynchronisesAfterGarbage) {
  // 3 garbage bytes, a fragment of 6 cut short by a new '<', then two whole packets.
  const std::string good1 = reply("CAAAAAAAAAAA", 1, 0);
  const std::string good2 = reply("DAAAAAAAAAAA", 3, 0);
  const std::string stream = "xy>" + good1.substr(0, 6) + good1 + good2;
  PacketAssembler a;
  Reply s;
  EXPECT_EQ(a.feed(reinterpret_cast<const uint8_t*>(stream.data()), stream.size(), &s), 2);
  EXPECT_EQ(s.encoder[0], 3);  // the latest packet wins
  EXPECT_EQ(s.homed, 3);
  EXPECT_EQ(a.droppedBytes(), 3u + 6u);
}

TEST(FalconProtocol, AssemblerDropsA16ByteRunWithoutEnd) {
  std::string bad = reply("AAAAAAAAAAAA", 0, 0);
  bad[15] = 'A';
  const std::string good = reply("BAAAAAAAAAAA", 0, 0);
  const std::string stream = bad + good;
  PacketAssembler a;
  Reply s;
  EXPECT_EQ(a.feed(reinterpret_cast<const uint8_t*>(stream.data()), stream.size(), &s), 1);
  EXPECT_EQ(s.encoder[0], 1);
  EXPECT_EQ(a.droppedBytes(), 16u);
}

TEST(FalconProtocol, LoaderHelloReplyWithOrWithoutNul) {
  const uint8_t plain[] = {0x0A, 0x44, 0x2C, 0x0D};
  const uint8_t nul[] = {0x00, 0x0A, 0x44, 0x2C, 0x0D};
  const uint8_t wrong[] = {0x0A, 0x43, 0x2C, 0x0D};
  EXPECT_TRUE(isLoaderHelloReply(plain, 4));
  EXPECT_TRUE(isLoaderHelloReply(nul, 5));
  EXPECT_FALSE(isLoaderHelloReply(wrong, 4));
  EXPECT_FALSE(isLoaderHelloReply(plain, 3));
}

TEST(FalconProtocol, BaudDivisorsGiveTheDocumentedRates) {
  // 3 MHz / (integer + fraction), the fraction 0.5 coded as bit 14.
  auto rate = [](uint16_t v) {
    const double fraction = (v >> 14) == 1 ? 0.5 : (v >> 14) == 2 ? 0.25 : (v >> 14) == 3 ? 0.125 : 0.0;
    return 3.0e6 / ((v & 0x3FFF) + fraction);
  };
  EXPECT_DOUBLE_EQ(rate(ftdi::kBaud9600), 9600.0);
  EXPECT_NEAR(rate(ftdi::kBaudLoader), 140000.0, 0.025 * 140000.0);
  EXPECT_DOUBLE_EQ(rate(ftdi::kBaudFirmware), 1.5e6);
}

}  // namespace
}  // namespace dentsim::devices::falcon
