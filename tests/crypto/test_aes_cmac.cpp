// AES-128 (bitsliced, constant time) and AES-128-CMAC against published
// vectors only: FIPS 197 Appendix C.1, the S-box as the field inverse and
// affine map of FIPS 197 5.1.1 (computed here from its definition, for all
// 256 inputs), and the four examples of RFC 4493 / NIST SP 800-38B (message
// lengths 0, 16, 40 and 64 bytes), split at every position.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <vector>

#include "heap_guard.hpp"
#include "hex.hpp"
#include "itp/crypto/aes128.hpp"
#include "itp/crypto/aes_cmac.hpp"
#include "itp/crypto/constant_time.hpp"

using crypto_test::from_hex;
using crypto_test::to_hex;
using namespace itp::crypto;

namespace {

std::array<std::uint8_t, 16> block_of(const std::string& hex) {
  const auto v = from_hex(hex);
  REQUIRE(v.size() == 16);
  std::array<std::uint8_t, 16> b{};
  std::copy(v.begin(), v.end(), b.begin());
  return b;
}

// GF(2^8) product with the AES polynomial, the textbook way (test reference only).
std::uint8_t gf_mul(std::uint8_t a, std::uint8_t b) {
  std::uint8_t p = 0;
  for (int i = 0; i < 8; ++i) {
    if ((b & 1u) != 0u) p = static_cast<std::uint8_t>(p ^ a);
    const bool high = (a & 0x80u) != 0u;
    a = static_cast<std::uint8_t>(a << 1);
    if (high) a = static_cast<std::uint8_t>(a ^ 0x1Bu);
    b = static_cast<std::uint8_t>(b >> 1);
  }
  return p;
}

// FIPS 197 5.1.1: the multiplicative inverse (0 -> 0), then b ^ rotl(b,1..4) ^ 0x63.
std::uint8_t sbox_by_definition(std::uint8_t x) {
  std::uint8_t inv = 0;
  for (int c = 1; c < 256 && x != 0; ++c) {
    if (gf_mul(x, static_cast<std::uint8_t>(c)) == 1u) inv = static_cast<std::uint8_t>(c);
  }
  std::uint8_t s = 0x63u;
  for (int i = 0; i < 5; ++i) {
    s = static_cast<std::uint8_t>(s ^ ((inv << i) | (inv >> ((8 - i) % 8))));
  }
  return s;
}

const std::string kRfcKey = "2b7e151628aed2a6abf7158809cf4f3c";
const std::string kRfcMessage =
    "6bc1bee22e409f96e93d7e117393172a"
    "ae2d8a571e03ac9c9eb76fac45af8e51"
    "30c81c46a35ce411e5fbc1191a0a52ef"
    "f69f2445df4f9b17ad2b417be66c3710";

struct RfcExample {
  std::size_t length;
  const char* tag;
};
constexpr RfcExample kRfcExamples[] = {
    {0, "bb1d6929e95937287fa37d129b756746"},
    {16, "070a16b46b4d4144f79bdd9dd04a287c"},
    {40, "dfa66747de9ae63030ca32611497c827"},
    {64, "51f0bebf7e3b9d92fc49741779363cfe"},
};

}  // namespace

TEST_CASE("AES-128: the S-box circuit is the field inverse and affine map for all 256 bytes") {
  // 16 bytes per run, one per bit position of the planes (bits 16..31 repeat them).
  int agreed = 0;
  for (int first = 0; first < 256; first += 16) {
    std::array<std::uint32_t, 8> planes{};
    for (int j = 0; j < 16; ++j) {
      for (int b = 0; b < 8; ++b) {
        const std::uint32_t bit = (static_cast<std::uint32_t>(first + j) >> b) & 1u;
        planes[static_cast<std::size_t>(b)] |= (bit << j) | (bit << (j + 16));
      }
    }
    aes_sub_bytes_planes(planes);
    for (int j = 0; j < 16; ++j) {
      std::uint8_t low = 0, high = 0;
      for (int b = 0; b < 8; ++b) {
        low = static_cast<std::uint8_t>(low | (((planes[static_cast<std::size_t>(b)] >> j) & 1u) << b));
        high = static_cast<std::uint8_t>(high | (((planes[static_cast<std::size_t>(b)] >> (j + 16)) & 1u) << b));
      }
      const std::uint8_t expected = sbox_by_definition(static_cast<std::uint8_t>(first + j));
      agreed += (low == expected && high == expected) ? 1 : 0;
    }
  }
  CHECK(agreed == 256);
  CHECK(sbox_by_definition(0x00) == 0x63);  // FIPS 197 Figure 7
  CHECK(sbox_by_definition(0x53) == 0xED);
}

TEST_CASE("AES-128: FIPS 197 Appendix C.1, and the bit-plane layout round-trips") {
  const auto key = block_of("000102030405060708090a0b0c0d0e0f");
  const auto plain = block_of("00112233445566778899aabbccddeeff");
  std::array<std::uint8_t, 16> out{};
  {
    test_support::HeapGuard guard;
    const Aes128 aes(key);
    aes.encrypt(plain, out);
  }
  CHECK(to_hex(out) == "69c4e0d86a7b0430d8cdb78070b4c55a");
  // In place.
  const Aes128 aes(key);
  auto inplace = plain;
  aes.encrypt(inplace, inplace);
  CHECK(inplace == out);
  // FIPS 197 Appendix B (the other published AES-128 example).
  const Aes128 b(block_of("2b7e151628aed2a6abf7158809cf4f3c"));
  b.encrypt(block_of("3243f6a8885a308d313198a2e0370734"), out);
  CHECK(to_hex(out) == "3925841d02dc09fbdc118597196a0b32");
  // RFC 4493 2.4: AES-128(K, 0^128), the L from which K1 and K2 come.
  b.encrypt(std::array<std::uint8_t, 16>{}, out);
  CHECK(to_hex(out) == "7df76b0c1ab899b33e42f047b91b546f");
  for (std::size_t v = 0; v < 256; ++v) {
    std::array<std::uint8_t, 16> in{};
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = static_cast<std::uint8_t>(v * 17 + i * 29);
    std::array<std::uint8_t, 16> back{};
    AesPlanes::load(in).store(back);
    REQUIRE(back == in);
  }
}

TEST_CASE("AES-128: wipe() overwrites the round keys") {
  Aes128 aes(block_of("000102030405060708090a0b0c0d0e0f"));
  aes.wipe();
  const Aes128 zero_schedule{};  // all-zero round keys, never set
  std::array<std::uint8_t, 16> a{}, b{};
  const auto plain = block_of("00112233445566778899aabbccddeeff");
  aes.encrypt(plain, a);
  zero_schedule.encrypt(plain, b);
  CHECK(a == b);
}

TEST_CASE("AES-128-CMAC: RFC 4493 examples 1-4 (lengths 0, 16, 40, 64)") {
  const CmacKey key(block_of(kRfcKey));
  const auto msg = from_hex(kRfcMessage);
  for (const RfcExample& ex : kRfcExamples) {
    CAPTURE(ex.length);
    CHECK(to_hex(aes_cmac(key, std::span<const std::uint8_t>(msg.data(), ex.length))) == ex.tag);
  }
}

TEST_CASE("AES-128-CMAC: the same tag for every split of each RFC 4493 message, byte by byte too, without heap") {
  const CmacKey key(block_of(kRfcKey));
  const auto msg = from_hex(kRfcMessage);
  int checked = 0;
  for (const RfcExample& ex : kRfcExamples) {
    for (std::size_t cut = 0; cut <= ex.length; ++cut) {
      for (std::size_t cut2 = cut; cut2 <= ex.length; ++cut2) {  // three pieces: every pair of cuts
        CmacTag tag{};
        {
          test_support::HeapGuard guard;
          Cmac mac(key);
          mac.update(std::span<const std::uint8_t>(msg.data(), cut));
          mac.update(std::span<const std::uint8_t>(msg.data() + cut, cut2 - cut));
          mac.update(std::span<const std::uint8_t>(msg.data() + cut2, ex.length - cut2));
          tag = mac.finish();
        }
        REQUIRE(to_hex(tag) == ex.tag);
        ++checked;
      }
    }
    Cmac bytewise(key);
    for (std::size_t i = 0; i < ex.length; ++i) bytewise.update(msg[i]);
    CHECK(to_hex(bytewise.finish()) == ex.tag);
  }
  CHECK(checked == 1 + 153 + 861 + 2145);
}

TEST_CASE("AES-128-CMAC: a truncated tag is the tag's first bytes") {
  const CmacKey key(block_of(kRfcKey));
  const auto msg = from_hex(kRfcMessage);
  Cmac mac(key);
  mac.update(std::span<const std::uint8_t>(msg.data(), 40));
  std::array<std::uint8_t, 8> tag8{};
  mac.finish(tag8);
  CHECK(to_hex(tag8) == "dfa66747de9ae630");
}

TEST_CASE("constant-time comparison: equal only for equal length and bytes") {
  const std::vector<std::uint8_t> a{1, 2, 3, 4};
  std::vector<std::uint8_t> b = a;
  CHECK(equal_constant_time(a, b));
  for (std::size_t i = 0; i < b.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      b = a;
      b[i] = static_cast<std::uint8_t>(b[i] ^ (1u << bit));
      CHECK_FALSE(equal_constant_time(a, b));
    }
  }
  CHECK_FALSE(equal_constant_time(a, std::vector<std::uint8_t>{1, 2, 3}));
  std::array<std::uint8_t, 5> secret{9, 9, 9, 9, 9};
  secure_wipe(secret.data(), secret.size());
  CHECK(secret == std::array<std::uint8_t, 5>{});
}
