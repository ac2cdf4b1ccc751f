// The Falcon's wire protocol without libusb: FTDI requests, the boot loader handshake, and the 16-byte packet codec.
//
// Sources: the FTDI FT232 vendor request set (reset/purge, modem control, flow control, baud
// divisor, line properties, latency timer) and the open Falcon driver community's notes on the
// Novint firmware: commands and replies are 16 ASCII bytes, '<' 14 payload bytes '>', each payload
// byte carrying one nibble as 'A' + nibble.
//
// Contents
//   1. USB and FTDI constants
//   2. The boot loader handshake (firmware load)
//   3. Packets: Command -> bytes, bytes -> Reply
//   4. PacketAssembler: packets out of a byte stream that USB splits anywhere
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace dentsim::devices::falcon {

// ---- 1. USB and FTDI constants ------------------------------------------------------------------
inline constexpr uint16_t kVendorId = 0x0403;   // FTDI
inline constexpr uint16_t kProductId = 0xCB48;  // the Falcon's own product id on an FTDI chip
inline constexpr uint8_t kEndpointOut = 0x02;   // bulk OUT
inline constexpr uint8_t kEndpointIn = 0x81;    // bulk IN
inline constexpr int kInterface = 0;
inline constexpr size_t kUsbPacketSize = 64;    // full-speed bulk max packet [bytes]
inline constexpr size_t kModemStatusSize = 2;   // the FTDI puts its modem status before each USB packet's data

namespace ftdi {
inline constexpr uint8_t kRequestTypeOut = 0x40;  // vendor, host to device, device recipient
// bRequest
inline constexpr uint8_t kReset = 0x00;
inline constexpr uint8_t kModemControl = 0x01;
inline constexpr uint8_t kFlowControl = 0x02;
inline constexpr uint8_t kBaudRate = 0x03;
inline constexpr uint8_t kLineProperties = 0x04;
inline constexpr uint8_t kLatencyTimer = 0x09;
// wValue of kReset
inline constexpr uint16_t kPurgeRx = 1;
inline constexpr uint16_t kPurgeTx = 2;
// wValue of kModemControl: the high byte says which lines change, the low byte their new level
inline constexpr uint16_t kDtrLow = 0x0100;
inline constexpr uint16_t kDtrHigh = 0x0101;
inline constexpr uint16_t kRtsLow = 0x0200;
// wValue of kLineProperties: 8 data bits, no parity, 1 stop bit
inline constexpr uint16_t kLine8N1 = 0x0008;
// wValue of kFlowControl (wIndex high byte 0): none
inline constexpr uint16_t kNoFlowControl = 0x0000;
// wValue of kBaudRate: 3 MHz / divisor, the divisor's fraction in bits 14-15 (0b01 = 0.5).
inline constexpr uint16_t kBaud9600 = 0x4138;     // 312.5 -> 9600 baud: the boot loader's rate
inline constexpr uint16_t kBaudLoader = 0x0015;   // 21 -> 142 857 baud: the firmware upload rate
inline constexpr uint16_t kBaudFirmware = 0x0002; // 2 -> 1.5 Mbaud: the running firmware's rate
inline constexpr uint16_t kLatencyLoader = 16;    // [ms] the boot loader misses bytes at 1 ms
inline constexpr uint16_t kLatencyFirmware = 1;   // [ms] one packet per millisecond
}  // namespace ftdi

// One vendor control request (no data stage), as the FTDI expects it on endpoint 0.
struct ControlRequest {
  uint8_t request_type = ftdi::kRequestTypeOut;
  uint8_t request = 0;
  uint16_t value = 0;
  uint16_t index = 0;  // 0: the chip's only port
  constexpr bool operator==(const ControlRequest&) const = default;
};

// The requests that put the FTDI in the running firmware's mode (after a load, or on open).
inline constexpr std::array<ControlRequest, 4> kFirmwareModeRequests = {{
    {ftdi::kRequestTypeOut, ftdi::kLatencyTimer, ftdi::kLatencyFirmware, 0},
    {ftdi::kRequestTypeOut, ftdi::kBaudRate, ftdi::kBaudFirmware, 0},
    {ftdi::kRequestTypeOut, ftdi::kReset, ftdi::kPurgeRx, 0},
    {ftdi::kRequestTypeOut, ftdi::kReset, ftdi::kPurgeTx, 0},
}};

// ---- 2. The boot loader handshake -------------------------------------------------------------
// Before a load: purge, slow the FTDI down for the boot loader, and pulse DTR to reset the
// microcontroller into it.
inline constexpr std::array<ControlRequest, 9> kLoaderModeRequests = {{
    {ftdi::kRequestTypeOut, ftdi::kReset, ftdi::kPurgeRx, 0},
    {ftdi::kRequestTypeOut, ftdi::kReset, ftdi::kPurgeTx, 0},
    {ftdi::kRequestTypeOut, ftdi::kLatencyTimer, ftdi::kLatencyLoader, 0},
    {ftdi::kRequestTypeOut, ftdi::kBaudRate, ftdi::kBaud9600, 0},
    {ftdi::kRequestTypeOut, ftdi::kLineProperties, ftdi::kLine8N1, 0},
    {ftdi::kRequestTypeOut, ftdi::kFlowControl, ftdi::kNoFlowControl, 0},
    {ftdi::kRequestTypeOut, ftdi::kModemControl, ftdi::kRtsLow, 0},
    {ftdi::kRequestTypeOut, ftdi::kModemControl, ftdi::kDtrLow, 0},
    {ftdi::kRequestTypeOut, ftdi::kModemControl, ftdi::kDtrHigh, 0},
}};
// The boot loader's greeting: we send LF 'C' CR, it answers LF 'D' ',' CR (some hosts see a NUL first).
inline constexpr std::array<uint8_t, 3> kLoaderHello = {0x0A, 0x43, 0x0D};
inline constexpr std::array<uint8_t, 4> kLoaderHelloReply = {0x0A, 0x44, 0x2C, 0x0D};
// Then DTR low and the upload rate, and one 'A' that the loader echoes before taking the image.
inline constexpr std::array<ControlRequest, 2> kLoaderUploadRequests = {{
    {ftdi::kRequestTypeOut, ftdi::kModemControl, ftdi::kDtrLow, 0},
    {ftdi::kRequestTypeOut, ftdi::kBaudRate, ftdi::kBaudLoader, 0},
}};
inline constexpr uint8_t kLoaderStart = 0x41;
// The image goes out in chunks of this size; the loader echoes every chunk byte for byte.
inline constexpr size_t kFirmwareChunk = 128;

// True when `reply` (modem status already stripped) is the loader's greeting, with or without
// the leading NUL.
bool isLoaderHelloReply(const uint8_t* reply, size_t size);

// ---- 3. Packets -------------------------------------------------------------------------------
inline constexpr size_t kPacketSize = 16;
using Packet = std::array<uint8_t, kPacketSize>;

// Output bits of the command's status nibble.
inline constexpr uint8_t kHomingMode = 0x1;  // the firmware homes an axis when it passes its index
inline constexpr uint8_t kLedGreen = 0x2;
inline constexpr uint8_t kLedBlue = 0x4;
inline constexpr uint8_t kLedRed = 0x8;
inline constexpr uint8_t kAllAxesHomed = 0x7;  // one bit per motor in Reply::homed

struct Command {
  std::array<int16_t, 3> motor{};  // motor words, signed, as the amplifiers take them
  uint8_t leds = 0;                // kLed* bits
  bool homing = false;             // homing mode on
};

struct Reply {
  std::array<int16_t, 3> encoder{};  // encoder counts, signed 16-bit, one per motor
  uint8_t homed = 0;                 // bit i: motor i has found its index (kAllAxesHomed: all)
  uint8_t grip = 0;                  // the grip's button bits
};

// '<', motor i as four nibbles least significant first, the status nibble, 'A', '>'; every
// payload byte is 'A' + nibble.
Packet encodeCommand(const Command& c);
// The reverse for the firmware's reply: encoders in bytes 1-12 like the motor words, byte 13 holding
// the homing bits (4-6) and the grip bits (0-3). False when the framing or a nibble byte is wrong.
bool decodeStatus(const uint8_t* packet, Reply* out);

// Copies the payload of a bulk IN transfer into out, dropping the two modem status bytes that lead
// every 64-byte USB packet in it. out needs room for `size` bytes; returns the bytes written.
size_t stripModemStatus(const uint8_t* transfer, size_t size, uint8_t* out);

// ---- 4. PacketAssembler -----------------------------------------------------------------------
// Finds packets in the byte stream: a packet may arrive split over several transfers, several may
// arrive at once, and after garbage (a partial packet at start-up, a line error) it resynchronises
// on the next '<'. Never allocates.
class PacketAssembler {
 public:
  // Feeds bytes; each complete, valid packet overwrites *latest. Returns the packets decoded.
  int feed(const uint8_t* bytes, size_t size, Reply* latest);
  uint64_t droppedBytes() const { return dropped_; }  // bytes thrown away while resynchronising
  void reset() { fill_ = 0; }

 private:
  Packet buffer_{};
  size_t fill_ = 0;  // bytes of the packet being assembled
  uint64_t dropped_ = 0;
};

}  // namespace dentsim::devices::falcon
