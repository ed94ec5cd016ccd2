// AES-128-CMAC cross-checked with an independent implementation: OpenSSL 3's
// EVP_MAC "CMAC" with cipher AES-128-CBC, on 2000 random keys and messages
// of random length 0-4096 bytes (the first 100 trials take lengths 0-99, so
// every residue mod 16 and the block boundaries occur), fed to ours in
// random pieces.
#include <doctest/doctest.h>

#include <array>
#include <random>
#include <vector>

#include "itp/crypto/aes_cmac.hpp"
#include "openssl_cmac.hpp"

TEST_CASE("AES-128-CMAC agrees with OpenSSL's CMAC on 2000 random keys and messages of 0-4096 bytes") {
  std::mt19937 rng(4493);
  int agreed = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<std::uint8_t, 16> key{};
    for (auto& b : key) b = static_cast<std::uint8_t>(rng());
    std::vector<std::uint8_t> msg(trial < 100 ? static_cast<std::size_t>(trial) : rng() % 4097);
    for (auto& b : msg) b = static_cast<std::uint8_t>(rng());
    const auto expected = itp_test::openssl_cmac(key.data(), msg.data(), msg.size());
    const itp::crypto::CmacKey k(key);
    // One shot, and in random pieces.
    const auto one_shot = itp::crypto::aes_cmac(k, msg);
    itp::crypto::Cmac pieces(k);
    for (std::size_t at = 0; at < msg.size();) {
      const std::size_t n = std::min<std::size_t>(msg.size() - at, rng() % 40);
      pieces.update(std::span<const std::uint8_t>(msg.data() + at, n));
      at += n;
    }
    const auto incremental = pieces.finish();
    agreed += (one_shot == expected && incremental == expected) ? 1 : 0;
  }
  CHECK(agreed == 2000);
}
