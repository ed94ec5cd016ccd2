#pragma once
// Consistent Overhead Byte Stuffing: removes every 0x00 from a frame so that
// 0x00 can delimit frames on the wire. Overhead: one byte per 254 bytes, plus one.
#include <cstddef>
#include <cstdint>
#include <span>

namespace itp::link {

constexpr std::size_t cobs_max_encoded_size(std::size_t raw_size) {
  return raw_size + raw_size / 254 + 1;
}

// Streaming encoder into a caller's buffer; bytes are pushed one at a time so
// a frame can be encoded from several pieces (header, payload, CRC) without a
// scratch copy.
class CobsWriter {
 public:
  explicit CobsWriter(std::span<std::uint8_t> out);
  void push(std::uint8_t byte);
  void push(std::span<const std::uint8_t> bytes);
  // Closes the last block. Returns the encoded size, or 0 if `out` was too small.
  std::size_t finish();

 private:
  std::span<std::uint8_t> out_;
  std::size_t code_index_ = 0;  // where the current block's code byte goes
  std::size_t next_ = 1;        // next free byte in out_
  std::uint8_t code_ = 1;       // 1 + bytes in the current block
  bool overflow_ = false;
};

// Decodes one encoded frame (without its delimiter). `out` may alias `in` with
// out.data() == in.data() (in-place decoding). Returns the decoded size, or
// 0 when the input is not valid COBS (a zero byte, a code running past the
// end) or does not fit.
std::size_t cobs_decode(std::span<const std::uint8_t> in, std::span<std::uint8_t> out);

}  // namespace itp::link
