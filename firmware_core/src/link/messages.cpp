#include "itp/link/messages.hpp"

#include "itp/link/byte_codec.hpp"

namespace itp::link {
namespace {

void put_counters(ByteWriter& w, const FirmwareCounters& c) {
  for (std::uint32_t v : {c.link.frames_ok, c.link.cobs_errors, c.link.length_errors, c.link.crc_errors,
                          c.link.version_errors, c.link.overflows, c.auth.accepted, c.auth.bad_tag,
                          c.auth.stale, c.auth.no_session, c.auth.handshakes, c.auth.handshakes_refused,
                          c.auth.malformed, c.auth.no_key, c.messages, c.too_large, c.resent, c.duplicates}) {
    w.u32(v);  // kCounterWords values
  }
}

FirmwareCounters get_counters(ByteReader& r) {
  FirmwareCounters c;
  std::uint32_t* fields[] = {&c.link.frames_ok, &c.link.cobs_errors, &c.link.length_errors, &c.link.crc_errors,
                             &c.link.version_errors, &c.link.overflows, &c.auth.accepted, &c.auth.bad_tag,
                             &c.auth.stale, &c.auth.no_session, &c.auth.handshakes, &c.auth.handshakes_refused,
                             &c.auth.malformed, &c.auth.no_key, &c.messages, &c.too_large, &c.resent, &c.duplicates};
  static_assert(sizeof(fields) / sizeof(fields[0]) == kCounterWords, "Pong counter layout");
  for (std::uint32_t* f : fields) {  // kCounterWords values
    *f = r.u32();
  }
  return c;
}

std::size_t finish(const ByteWriter& w) { return w.ok() ? w.size() : 0; }

// ErrorReply and AuthErrorReply: a one-byte code, then the request's type.
template <class Reply>
std::size_t encode_code_reply(const Reply& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u8(static_cast<std::uint8_t>(msg.code));
  w.u8(msg.request_type);
  return finish(w);
}

template <class Reply>
bool decode_code_reply(std::span<const std::uint8_t> in, Reply& msg) {
  ByteReader r(in);
  msg.code = static_cast<decltype(msg.code)>(r.u8());
  msg.request_type = r.u8();
  return r.done();
}

}  // namespace

std::size_t encode(const Ping& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u32(msg.nonce);
  return finish(w);
}

std::size_t encode(const Pong& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u32(msg.nonce);
  w.u8(msg.protocol_version);
  for (char c : msg.build_id) {  // kBuildIdBytes
    w.u8(static_cast<std::uint8_t>(c));
  }
  put_counters(w, msg.counters);
  w.u64(msg.ticks);
  w.u64(msg.tick_hz);
  return finish(w);
}

std::size_t encode(const ErrorReply& msg, std::span<std::uint8_t> out) { return encode_code_reply(msg, out); }

std::size_t encode(const AuthErrorReply& msg, std::span<std::uint8_t> out) { return encode_code_reply(msg, out); }

std::size_t encode(const SegmentReport& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u8(msg.type);
  w.u16(msg.sequence);
  w.bytes(msg.segments.bytes());
  return finish(w);
}

std::size_t encode(const Diagnostics& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u32(msg.stack_bytes);
  w.u32(msg.stack_peak_bytes);
  return finish(w);
}

bool decode(std::span<const std::uint8_t> in, Ping& msg) {
  ByteReader r(in);
  msg.nonce = r.u32();
  return r.done();
}

bool decode(std::span<const std::uint8_t> in, Pong& msg) {
  ByteReader r(in);
  msg.nonce = r.u32();
  msg.protocol_version = r.u8();
  for (char& c : msg.build_id) {  // kBuildIdBytes
    c = static_cast<char>(r.u8());
  }
  msg.counters = get_counters(r);
  msg.ticks = r.u64();
  msg.tick_hz = r.u64();
  // The build id must be NUL-terminated inside its field.
  return r.done() && msg.build_id.back() == '\0';
}

bool decode(std::span<const std::uint8_t> in, ErrorReply& msg) { return decode_code_reply(in, msg); }

bool decode(std::span<const std::uint8_t> in, AuthErrorReply& msg) { return decode_code_reply(in, msg); }

bool decode(std::span<const std::uint8_t> in, SegmentReport& msg) {
  ByteReader r(in);
  msg.type = r.u8();
  msg.sequence = r.u16();
  for (std::uint8_t& b : msg.segments.bytes()) {  // SegmentSet::kBytes
    b = r.u8();
  }
  return r.done();
}

bool decode(std::span<const std::uint8_t> in, Diagnostics& msg) {
  ByteReader r(in);
  msg.stack_bytes = r.u32();
  msg.stack_peak_bytes = r.u32();
  return r.done();
}

void set_build_id(Pong& msg, const char* text) {
  msg.build_id.fill('\0');
  for (std::size_t i = 0; i + 1 < msg.build_id.size() && text[i] != '\0'; ++i) {  // kBuildIdBytes
    msg.build_id[i] = text[i];
  }
}

}  // namespace itp::link
