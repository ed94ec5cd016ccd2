#include "link/fault_injection.hpp"

#include <algorithm>
#include <sstream>

namespace hil {

std::optional<LinkFaults> parse_link_faults(const std::string& spec, std::string& error) {
  LinkFaults f;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      error = "'" + item + "' is not NAME=VALUE";
      return std::nullopt;
    }
    const std::string name = item.substr(0, eq);
    const std::string value = item.substr(eq + 1);
    try {
      std::size_t used = 0;
      if (name == "seed") {
        f.seed = std::stoull(value, &used);
      } else {
        const double p = std::stod(value, &used);
        if (!(p >= 0.0 && p <= 1.0)) {
          error = "'" + item + "': a probability in [0, 1]";
          return std::nullopt;
        }
        if (name == "drop") f.drop = p;
        else if (name == "dup") f.dup = p;
        else if (name == "flip") f.flip = p;
        else if (name == "reorder") f.reorder = p;
        else if (name == "bytes") f.drop = f.dup = f.flip = f.reorder = p / 4.0;
        else {
          error = "unknown fault '" + name + "' (drop, dup, flip, reorder, bytes, seed)";
          return std::nullopt;
        }
      }
      if (used != value.size()) throw std::invalid_argument(value);
    } catch (const std::exception&) {
      error = "'" + item + "': not a number";
      return std::nullopt;
    }
  }
  if (f.total() > 1.0) {
    error = "the fault probabilities add up to more than 1";
    return std::nullopt;
  }
  return f;
}

std::string to_string(const LinkFaults& f) {
  std::ostringstream s;
  s << "drop=" << f.drop << ",dup=" << f.dup << ",flip=" << f.flip << ",reorder=" << f.reorder << ",seed=" << f.seed;
  return s.str();
}

FaultyTransport::FaultyTransport(ByteTransport& inner, const LinkFaults& faults)
    : inner_(inner), faults_(faults), rng_(faults.seed) {}

// One draw per byte picks at most one fault: drop, duplicate, flip, reorder
// (in that order of the probability line), else the byte passes.
void FaultyTransport::corrupt(Direction& d, std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::uint8_t b : in) {
    ++d.counters.bytes;
    const double x = u(rng_);
    double edge = faults_.drop;
    std::uint8_t emit[2] = {b, b};
    int count = 1;
    if (x < edge) {
      ++d.counters.dropped;
      count = 0;
    } else if (x < (edge += faults_.dup)) {
      ++d.counters.duplicated;
      count = 2;
    } else if (x < (edge += faults_.flip)) {
      ++d.counters.flipped;
      emit[0] = static_cast<std::uint8_t>(b ^ (1u << (rng_() % 8)));
    } else if (x < (edge += faults_.reorder) && !d.held) {
      ++d.counters.reordered;
      d.held = b;  // goes out after the next byte
      continue;
    }
    for (int k = 0; k < count; ++k) {
      out.push_back(emit[k]);
      if (d.held) {
        out.push_back(*d.held);
        d.held.reset();
      }
    }
  }
}

bool FaultyTransport::write_all(std::span<const std::uint8_t> bytes) {
  std::vector<std::uint8_t> out;
  out.reserve(bytes.size() + 8);
  corrupt(out_, bytes, out);
  return out.empty() || inner_.write_all(out);
}

std::size_t FaultyTransport::read_some(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) {
  if (pending_.empty()) {
    std::vector<std::uint8_t> raw(buffer.size());
    const std::size_t n = inner_.read_some(raw, timeout);
    corrupt(in_, std::span<const std::uint8_t>(raw.data(), n), pending_);
  }
  const std::size_t k = std::min(buffer.size(), pending_.size());
  std::copy_n(pending_.begin(), k, buffer.begin());
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(k));
  return k;
}

}  // namespace hil
