// libFuzzer target: the streaming frame decoder on arbitrary bytes. Every
// frame it accepts must be one our encoder produces from the same header
// and bytes: re-encoded, it COBS-decodes to the identical raw frame, and
// decodes again to the same header and chunk.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "itp/link/cobs.hpp"
#include "itp/link/frame_decoder.hpp"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

itp::link::FrameDecoder g_decoder;  // state carries across inputs, as on a line

// Scratch buffers of the checks, allocated once (a 64 KiB message zeroed and
// two wire frames allocated per accepted frame cost more than the decoding).
// g_message is all zeros between frames.
std::array<std::uint8_t, itp::link::kMaxMessageBytes> g_message{};
std::array<std::uint8_t, itp::link::kMaxWireFrameBytes> g_wire{}, g_a{}, g_b{};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace itp::link;
  g_decoder.push(0u);  // each input starts on a fresh frame
  std::size_t start = 0;  // where the bytes of the frame being received begin
  for (std::size_t i = 0; i < size; ++i) {
    const std::size_t begin = start;
    if (data[i] == 0u) {
      start = i + 1;
    }
    if (g_decoder.push(data[i]) != DecodeResult::kFrame) {
      continue;
    }
    const std::span<const std::uint8_t> encoded(data + begin, i - begin);  // between the delimiters
    const FrameView f = g_decoder.frame();
    check(f.header.version == kProtocolVersion);
    check(valid_layout(f.header.message_length, f.header.segment_count, f.header.segment_index));
    check(f.chunk.size() == segment_length(f.header.message_length, f.header.segment_count, f.header.segment_index));
    // A message holding this chunk at its place (zeros elsewhere), re-encoded.
    // At the end of g_message, so that AddressSanitizer still sees a read past its end.
    const std::span<std::uint8_t> message(g_message.end() - f.header.message_length, f.header.message_length);
    const std::size_t offset = segment_offset(f.header.message_length, f.header.segment_count, f.header.segment_index);
    std::copy(f.chunk.begin(), f.chunk.end(), message.begin() + static_cast<long>(offset));
    std::array<std::uint8_t, kMaxWireFrameBytes>& wire = g_wire;
    wire.fill(0u);
    const std::size_t n = encode_segment(f.header, message, wire);
    std::fill(message.begin() + static_cast<long>(offset), message.begin() + static_cast<long>(offset + f.chunk.size()), 0u);
    check(n >= 2 && wire[0] == 0u && wire[n - 1] == 0u);
    // The same raw frame as the one received (COBS may encode it differently
    // only at a 254-byte block boundary, so compare after decoding).
    g_a.fill(0u);
    g_b.fill(0u);
    const std::size_t ra = cobs_decode(std::span<const std::uint8_t>(wire.data() + 1, n - 2), g_a);
    const std::size_t rb = cobs_decode(encoded, g_b);
    check(ra > 0 && ra == rb && std::equal(g_a.begin(), g_a.begin() + static_cast<long>(ra), g_b.begin()));
    FrameDecoder again;
    int frames = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (again.push(wire[k]) == DecodeResult::kFrame) {
        ++frames;
        const FrameView& g = again.frame();
        check(g.header.type == f.header.type && g.header.sequence == f.header.sequence &&
              g.header.message_length == f.header.message_length && g.header.segment_index == f.header.segment_index &&
              g.header.segment_count == f.header.segment_count && g.header.flags == f.header.flags &&
              g.header.answer_units == f.header.answer_units &&
              std::equal(g.chunk.begin(), g.chunk.end(), f.chunk.begin(), f.chunk.end()));
      }
    }
    check(frames == 1);
  }
  return 0;
}
