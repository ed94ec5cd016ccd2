#include "itp/link/cobs.hpp"

namespace itp::link {

CobsWriter::CobsWriter(std::span<std::uint8_t> out) : out_(out) {
  overflow_ = out_.empty();
}

void CobsWriter::push(std::uint8_t byte) {
  if (overflow_) {
    return;
  }
  if (byte != 0u) {
    if (next_ >= out_.size()) {
      overflow_ = true;
      return;
    }
    out_[next_++] = byte;
    ++code_;
  }
  // A zero ends the block; so does a block that reached 254 data bytes.
  if (byte == 0u || code_ == 0xFFu) {
    out_[code_index_] = code_;
    code_ = 1;
    code_index_ = next_;
    if (next_ >= out_.size()) {
      overflow_ = true;
      return;
    }
    ++next_;
  }
}

void CobsWriter::push(std::span<const std::uint8_t> bytes) {
  for (std::uint8_t b : bytes) {  // bounded by the span length
    push(b);
  }
}

std::size_t CobsWriter::finish() {
  if (overflow_) {
    return 0;
  }
  out_[code_index_] = code_;
  return next_;
}

std::size_t cobs_decode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) {
  std::size_t read = 0;
  std::size_t written = 0;
  // Each pass consumes one block (>= 1 byte), so the loop runs at most in.size() times.
  while (read < in.size()) {
    const std::uint8_t code = in[read++];
    if (code == 0u) {
      return 0;
    }
    const std::size_t block = static_cast<std::size_t>(code) - 1u;
    if (read + block > in.size() || written + block > out.size()) {
      return 0;
    }
    for (std::size_t i = 0; i < block; ++i) {  // bounded by 254
      const std::uint8_t b = in[read++];
      if (b == 0u) {
        return 0;
      }
      out[written++] = b;
    }
    // A block shorter than 254 bytes stands for a zero, except at the very end.
    if (code != 0xFFu && read < in.size()) {
      if (written >= out.size()) {
        return 0;
      }
      out[written++] = 0u;
    }
  }
  return written;
}

}  // namespace itp::link
