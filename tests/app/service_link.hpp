#pragma once
// Test plumbing: a ByteTransport that is a FirmwareService in this process,
// so that the simulator's LinkClient talks to the firmware's code without a
// child process. `drop_frame` lets a test lose chosen frames either way.
#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <vector>

#include "itp/app/firmware_service.hpp"
#include "itp/link/frame_decoder.hpp"
#include "link/byte_transport.hpp"

namespace app_test {

using Service = itp::app::FirmwareService<itp::DefaultConfig>;

// A link key (AES-128, 16 bytes) and boot entropy (32 bytes): test data, not secrets.
inline std::array<std::uint8_t, itp::link::kKeyBytes> test_key(std::uint8_t seed = 1) {
  std::array<std::uint8_t, itp::link::kKeyBytes> k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(seed + 17 * i);
  return k;
}

inline std::array<std::uint8_t, itp::link::kEntropyBytes> test_entropy(std::uint8_t seed = 99) {
  std::array<std::uint8_t, itp::link::kEntropyBytes> e{};
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = static_cast<std::uint8_t>(seed + 17 * i);
  return e;
}

template <class Svc = Service>
std::unique_ptr<Svc> provisioned_service(std::uint8_t key_seed = 1) {
  auto svc = std::make_unique<Svc>();
  const auto key = test_key(key_seed);
  const auto entropy = test_entropy(99);
  svc->provision(key, entropy);
  svc->set_build_id("itplan-unit");
  return svc;
}

template <class Svc>
class BasicServiceTransport final : public hil::ByteTransport {
 public:
  enum class Direction { kToFirmware, kToHost };
  // Returns true to lose this (whole, encoded) frame.
  using Filter = std::function<bool(Direction, const itp::link::FrameView&)>;

  explicit BasicServiceTransport(Svc& service) : service_(service) {}
  void set_filter(Filter f) { filter_ = std::move(f); }

  bool write_all(std::span<const std::uint8_t> bytes) override {
    for (std::uint8_t b : bytes) {
      pending_in_.push_back(b);
      if (b != 0u) continue;
      // A delimiter ends a frame: look at it, then hand it over (or not).
      const bool lose = filter_ && judge(pending_in_, Direction::kToFirmware);
      if (!lose) {
        for (std::uint8_t x : pending_in_) service_.on_byte(x);
      }
      pending_in_.clear();
      collect();
    }
    return true;
  }

  std::size_t read_some(std::span<std::uint8_t> buffer, std::chrono::milliseconds) override {
    const std::size_t n = std::min(buffer.size(), to_host_.size());
    std::copy_n(to_host_.begin(), n, buffer.begin());
    to_host_.erase(to_host_.begin(), to_host_.begin() + static_cast<long>(n));
    return n;
  }

 private:
  void collect() {
    for (auto f = service_.next_frame(); !f.empty(); f = service_.next_frame()) {
      if (filter_ && judge(std::vector<std::uint8_t>(f.begin(), f.end()), Direction::kToHost)) continue;
      to_host_.insert(to_host_.end(), f.begin(), f.end());
    }
  }
  bool judge(const std::vector<std::uint8_t>& bytes, Direction d) {
    itp::link::FrameDecoder dec;
    for (std::uint8_t b : bytes) {
      if (dec.push(b) == itp::link::DecodeResult::kFrame) return filter_(d, dec.frame());
    }
    return false;
  }

  Svc& service_;
  Filter filter_;
  std::vector<std::uint8_t> pending_in_;
  std::deque<std::uint8_t> to_host_;
};

using ServiceTransport = BasicServiceTransport<Service>;

}  // namespace app_test
