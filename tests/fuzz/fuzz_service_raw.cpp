// libFuzzer target: FirmwareService::on_byte on arbitrary bytes (a line
// with nothing but noise and forgeries on it). The service must never crash,
// every frame it sends must be valid, and without a session it must never
// plan (no secured message is ever accepted).
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static auto storage = std::make_unique<fuzz::Service>();
  static auto out = std::make_unique<fuzz::Replies>();
  static const std::array<std::uint8_t, 32> entropy{1, 2, 3};
  fuzz::Service& svc = fuzz::restart(storage.get(), entropy);  // each input meets a freshly started firmware
  out->reset();
  fuzz::feed(svc, *out, std::span<const std::uint8_t>(data, size));
  fuzz::check(svc.counters().auth.accepted == 0);  // nobody but the key holder opens a session
  return 0;
}
