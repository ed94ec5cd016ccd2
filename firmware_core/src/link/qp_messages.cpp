#include "itp/link/qp_messages.hpp"

namespace itp::link {

std::size_t encode(const QpSolveReply& msg, std::span<std::uint8_t> out) {
  ByteWriter w(out);
  w.u8(static_cast<std::uint8_t>(msg.status));
  w.u16(msg.iterations);
  w.u16(msg.n);
  w.f64(msg.objective);
  w.u64(msg.ticks);
  for (int i = 0; i < msg.n && i < DefaultConfig::kPathVariables; ++i) {  // n <= kPathVariables
    w.f64(msg.x[i]);
  }
  return w.ok() && msg.n <= DefaultConfig::kPathVariables ? w.size() : 0;
}

bool decode(std::span<const std::uint8_t> in, QpSolveReply& msg) {
  ByteReader r(in);
  msg.status = static_cast<qp::QpStatus>(r.u8());
  msg.iterations = r.u16();
  msg.n = r.u16();
  msg.objective = r.f64();
  msg.ticks = r.u64();
  if (msg.n > DefaultConfig::kPathVariables) {
    return false;
  }
  for (int i = 0; i < msg.n; ++i) {  // n <= kPathVariables
    msg.x[i] = r.f64();
  }
  return r.done();
}

}  // namespace itp::link
