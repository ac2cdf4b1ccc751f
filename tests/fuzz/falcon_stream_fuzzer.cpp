// libFuzzer entry for the Falcon's byte stream: modem status stripping, packet reassembly however USB splits it, single packets and the loader greeting.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "devices/falcon_protocol.h"

namespace {

namespace falcon = dentsim::devices::falcon;

void require(bool holds) {
  if (!holds) std::abort();
}

bool same(const falcon::Reply& a, const falcon::Reply& b) {
  return a.encoder == b.encoder && a.homed == b.homed && a.grip == b.grip;
}

// Homed and grip out of a reply's range: "no reply yet".
falcon::Reply sentinel() {
  falcon::Reply r;
  r.homed = 0xEE;
  r.grip = 0xEE;
  return r;
}

struct Whole {
  std::vector<falcon::Reply> replies;  // in order
  std::vector<size_t> ends;            // offset of each reply's last byte
  uint64_t dropped = 0;
};

// Byte by byte: every reply well-formed, and the bytes fed always equal those dropped, decoded and
// at most one packet's worth buffered.
Whole feedByteByByte(const std::vector<uint8_t>& s) {
  Whole w;
  falcon::PacketAssembler a;
  falcon::Reply latest = sentinel();
  for (size_t i = 0; i < s.size(); ++i) {
    const int got = a.feed(&s[i], 1, &latest);
    require(got == 0 || got == 1);
    if (got == 1) {
      require(latest.homed <= falcon::kAllAxesHomed && latest.grip <= 0xF);
      w.replies.push_back(latest);
      w.ends.push_back(i);
    }
    const uint64_t accounted = a.droppedBytes() + falcon::kPacketSize * w.replies.size();
    require(accounted <= i + 1 && i + 1 - accounted < falcon::kPacketSize);
  }
  w.dropped = a.droppedBytes();
  return w;
}

// The replies the stream holds by the contract alone: each '<' followed by 15 bytes without another
// '<' is a packet, its reply read by hand where its framing, 12 nibble bytes 'A'..'P' and status byte
// ('A' + 7 bits) are good; with the offset of its last byte.
void requireReference(const std::vector<uint8_t>& s, const Whole& w) {
  size_t k = 0;
  for (size_t p = 0; p + falcon::kPacketSize <= s.size(); ++p) {
    const uint8_t* b = &s[p];
    if (b[0] != '<' || std::find(b + 1, b + falcon::kPacketSize, uint8_t('<')) != b + falcon::kPacketSize) continue;
    if (b[15] != '>' || b[13] < 'A' || b[13] >= 'A' + 0x80) continue;
    if (!std::all_of(b + 1, b + 13, [](uint8_t c) { return c >= 'A' && c <= 'P'; })) continue;
    falcon::Reply r;
    for (size_t m = 0; m < 3; ++m) {
      unsigned bits = 0;
      for (size_t j = 0; j < 4; ++j) bits |= unsigned(b[1 + 4 * m + j] - 'A') << (4 * j);
      r.encoder[m] = int16_t(uint16_t(bits));
    }
    r.homed = uint8_t((b[13] - 'A') >> 4);
    r.grip = uint8_t((b[13] - 'A') & 0xF);
    require(k < w.replies.size() && w.ends[k] == p + 15 && same(w.replies[k], r));
    ++k;
  }
  require(k == w.replies.size());
}

// Split at k, the two feeds give the replies that end in each piece and the same bytes dropped.
void checkSplit(const std::vector<uint8_t>& s, const Whole& w, size_t k) {
  falcon::PacketAssembler a;
  falcon::Reply latest = sentinel();
  const size_t before = size_t(std::lower_bound(w.ends.begin(), w.ends.end(), k) - w.ends.begin());
  require(size_t(a.feed(s.data(), k, &latest)) == before);
  require(same(latest, before > 0 ? w.replies[before - 1] : sentinel()));
  require(size_t(a.feed(s.data() + k, s.size() - k, &latest)) == w.replies.size() - before);
  require(same(latest, w.replies.empty() ? sentinel() : w.replies.back()));
  require(a.droppedBytes() == w.dropped);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> s(data, data + size);

  const Whole w = feedByteByByte(s);
  requireReference(s, w);
  // Every split point of a short input; a few spread over a long one, so a case stays quick.
  if (size <= 256) {
    for (size_t k = 0; k <= size; ++k) checkSplit(s, w, k);
  } else {
    for (size_t j = 0; j <= 8; ++j) checkSplit(s, w, size * j / 8);
  }

  // The input as a bulk IN transfer: the payload, into exactly the documented room, is the input
  // without the first two bytes of every 64.
  std::vector<uint8_t> payload(size);
  const size_t n = falcon::stripModemStatus(s.data(), size, payload.data());
  size_t want = 0;
  for (size_t at = 0; at < size; at += falcon::kUsbPacketSize) {
    const size_t packet = std::min(size - at, falcon::kUsbPacketSize);
    if (packet > falcon::kModemStatusSize) {
      require(std::memcmp(payload.data() + want, s.data() + at + falcon::kModemStatusSize,
                             packet - falcon::kModemStatusSize) == 0);
      want += packet - falcon::kModemStatusSize;
    }
  }
  require(n == want);

  // One packet: a decoded reply is in range, and a refused one leaves the reply alone.
  if (size >= falcon::kPacketSize) {
    const std::vector<uint8_t> packet(s.begin(), s.begin() + falcon::kPacketSize);
    falcon::Reply r = sentinel();
    if (falcon::decodeStatus(packet.data(), &r)) {
      require(r.homed <= falcon::kAllAxesHomed && r.grip <= 0xF);
    } else {
      require(same(r, sentinel()));
    }
  }

  const auto& hello = falcon::kLoaderHelloReply;
  const bool greeting = (size == 4 && std::equal(hello.begin(), hello.end(), s.begin())) ||
                        (size == 5 && s[0] == 0 && std::equal(hello.begin(), hello.end(), s.begin() + 1));
  require(falcon::isLoaderHelloReply(s.data(), size) == greeting);
  return 0;
}
