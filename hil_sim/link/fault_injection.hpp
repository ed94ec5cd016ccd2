#pragma once
// A broken bus between the simulator and the firmware (hil_sim run
// --link-faults): a ByteTransport wrapper that drops, duplicates, flips a bit
// of, or swaps with its successor each byte with given probabilities, in
// both directions, from a seeded generator (the same seed, the same faults).
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "link/byte_transport.hpp"

namespace hil {

struct LinkFaults {
  double drop = 0.0;     // per byte, each direction
  double dup = 0.0;
  double flip = 0.0;     // one random bit of the byte
  double reorder = 0.0;  // the byte goes after the next one
  std::uint64_t seed = 1;

  bool any() const { return drop > 0 || dup > 0 || flip > 0 || reorder > 0; }
  double total() const { return drop + dup + flip + reorder; }
};

// "drop=P,dup=P,flip=P,reorder=P[,seed=N]" (any subset, any order);
// "bytes=P" sets all four to P/4. nullopt and `error` on a bad spec.
std::optional<LinkFaults> parse_link_faults(const std::string& spec, std::string& error);
std::string to_string(const LinkFaults& faults);

// Bytes seen and faults made in one direction.
struct FaultCounters {
  std::uint64_t bytes = 0;
  std::uint64_t dropped = 0;
  std::uint64_t duplicated = 0;
  std::uint64_t flipped = 0;
  std::uint64_t reordered = 0;

  std::uint64_t faults() const { return dropped + duplicated + flipped + reordered; }
};

class FaultyTransport final : public ByteTransport {
 public:
  FaultyTransport(ByteTransport& inner, const LinkFaults& faults);

  bool write_all(std::span<const std::uint8_t> bytes) override;  // host -> firmware
  std::size_t read_some(std::span<std::uint8_t> buffer,
                        std::chrono::milliseconds timeout) override;  // firmware -> host

  const FaultCounters& to_firmware() const { return out_.counters; }
  const FaultCounters& to_host() const { return in_.counters; }

 private:
  struct Direction {
    FaultCounters counters;
    std::optional<std::uint8_t> held;  // a byte waiting to be swapped with the next
  };
  void corrupt(Direction& d, std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out);

  ByteTransport& inner_;
  LinkFaults faults_;
  std::mt19937_64 rng_;
  Direction out_;
  Direction in_;
  std::vector<std::uint8_t> pending_;  // faulty bytes from the firmware not yet handed out
};

}  // namespace hil
