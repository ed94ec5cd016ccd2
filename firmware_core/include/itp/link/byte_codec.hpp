#pragma once
// Little-endian writer and reader over caller-owned byte spans. Running past
// the end sets a sticky error flag instead of writing or reading out of range,
// so a message codec checks once at the end.
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <cstdint>
#include <span>

namespace itp::link {

class ByteWriter {
 public:
  explicit ByteWriter(std::span<std::uint8_t> out) : out_(out) {}

  void u8(std::uint8_t v) {
    if (pos_ >= out_.size()) {
      ok_ = false;
      return;
    }
    out_[pos_++] = v;
  }
  void u16(std::uint16_t v) { uint_le(v, 2); }
  void u32(std::uint32_t v) { uint_le(v, 4); }
  void u64(std::uint64_t v) { uint_le(v, 8); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  // A double as float32. A finite value beyond float's range fails the write
  // (sticky, like running out of room) instead of silently becoming
  // infinity; NaN and infinities pass as they are (the receiver rejects them).
  void f32_of(double v) {
    if (std::isfinite(v) && std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
      ok_ = false;
      return;
    }
    f32(static_cast<float>(v));
  }
  void bytes(std::span<const std::uint8_t> b) {
    for (std::uint8_t x : b) {  // bounded by the span length
      u8(x);
    }
  }

  bool ok() const { return ok_; }
  std::size_t size() const { return pos_; }
  std::span<const std::uint8_t> written() const { return out_.first(pos_); }

 private:
  void uint_le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) {  // n <= 8
      u8(static_cast<std::uint8_t>(v >> (8 * i)));
    }
  }

  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> in) : in_(in) {}

  std::uint8_t u8() {
    if (pos_ >= in_.size()) {
      ok_ = false;
      return 0;
    }
    return in_[pos_++];
  }
  std::uint16_t u16() { return static_cast<std::uint16_t>(uint_le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(uint_le(4)); }
  std::uint64_t u64() { return uint_le(8); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  float f32() { return std::bit_cast<float>(u32()); }

  bool ok() const { return ok_; }
  // True when every byte was consumed and nothing ran past the end.
  bool done() const { return ok_ && pos_ == in_.size(); }

 private:
  std::uint64_t uint_le(int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) {  // n <= 8
      v |= static_cast<std::uint64_t>(u8()) << (8 * i);
    }
    return v;
  }

  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace itp::link
