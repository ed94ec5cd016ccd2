#pragma once
// Streaming frame decoder: feed it received bytes one at a time. It collects
// bytes up to each 0x00 delimiter, then checks COBS, length and segment
// layout, CRC and version. A bad frame is counted and dropped; after garbage
// or an overlong run the decoder resynchronises at the next delimiter. Its
// buffer holds one segment (kMaxWireFrameBytes), not a whole message.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/link/frame.hpp"

namespace itp::link {

// Why a frame was dropped, or that one arrived.
enum class DecodeResult : std::uint8_t {
  kPending = 0,    // no delimiter yet
  kFrame,          // a valid frame is available through frame()
  kEmpty,          // a lone delimiter (used to flush the line); ignored
  kCobsError,      // bytes between delimiters were not valid COBS
  kLengthError,    // shorter than a header + CRC, or the segment layout is impossible
  kCrcError,       // checksum mismatch
  kVersionError,   // valid frame of another protocol version
  kOverflow,       // more than kMaxWireFrameBytes without a delimiter
};

const char* to_string(DecodeResult result);

// Frames accepted and dropped, by reason. Both ends report theirs.
struct LinkCounters {
  std::uint32_t frames_ok = 0;
  std::uint32_t cobs_errors = 0;
  std::uint32_t length_errors = 0;
  std::uint32_t crc_errors = 0;
  std::uint32_t version_errors = 0;
  std::uint32_t overflows = 0;

  std::uint32_t dropped() const {
    return cobs_errors + length_errors + crc_errors + version_errors + overflows;
  }
};

struct FrameView {
  FrameHeader header;
  std::span<const std::uint8_t> chunk;  // this segment's bytes; valid until the next push()
};

class FrameDecoder {
 public:
  DecodeResult push(std::uint8_t byte);
  // The last frame, valid right after push() returned kFrame.
  const FrameView& frame() const { return frame_; }
  const LinkCounters& counters() const { return counters_; }
  void reset();

 private:
  DecodeResult finish_frame();

  std::array<std::uint8_t, kMaxWireFrameBytes> buffer_{};  // encoded, decoded in place
  std::size_t fill_ = 0;
  bool discarding_ = false;  // after an overflow, until the next delimiter
  FrameView frame_{};
  LinkCounters counters_{};
};

}  // namespace itp::link
