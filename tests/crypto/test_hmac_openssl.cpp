// HMAC-SHA-256 cross-checked with an independent implementation (OpenSSL)
// on random keys (0-200 bytes) and messages (0-3000 bytes): block-boundary
// lengths and keys longer than a block included.
#include <doctest/doctest.h>
#include <openssl/hmac.h>

#include <random>
#include <vector>

#include "itp/crypto/hmac_sha256.hpp"

TEST_CASE("HMAC-SHA-256 agrees with OpenSSL on 2000 random keys and messages") {
  std::mt19937 rng(4231);
  int agreed = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::uint8_t> key(rng() % 201);
    std::vector<std::uint8_t> msg(trial < 200 ? static_cast<std::size_t>(trial) : rng() % 3001);
    for (auto& b : key) b = static_cast<std::uint8_t>(rng());
    for (auto& b : msg) b = static_cast<std::uint8_t>(rng());
    unsigned char expected[EVP_MAX_MD_SIZE];
    unsigned int expected_len = 0;
    REQUIRE(HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), msg.data(), msg.size(), expected,
                 &expected_len) != nullptr);
    REQUIRE(expected_len == 32);
    const auto tag = itp::crypto::hmac_sha256(itp::crypto::HmacKey(key), msg);
    agreed += std::equal(tag.begin(), tag.end(), expected) ? 1 : 0;
  }
  CHECK(agreed == 2000);
}
