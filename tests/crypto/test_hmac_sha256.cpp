// HMAC-SHA-256 against the seven test cases of RFC 4231 (keys shorter than,
// equal to and longer than a block; case 5's output truncated to 128 bits,
// as the link truncates its tags), and the constant-time comparison.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "hex.hpp"
#include "itp/crypto/hmac_sha256.hpp"

using crypto_test::bytes_of;
using crypto_test::from_hex;
using crypto_test::to_hex;

namespace {

std::string hmac_hex(const std::vector<std::uint8_t>& key, const std::vector<std::uint8_t>& data) {
  const itp::crypto::HmacKey k(key);
  return to_hex(itp::crypto::hmac_sha256(k, data));
}

}  // namespace

TEST_CASE("HMAC-SHA-256: RFC 4231 test cases 1-7") {
  CHECK(hmac_hex(std::vector<std::uint8_t>(20, 0x0b), bytes_of("Hi There")) ==
        "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7");
  CHECK(hmac_hex(bytes_of("Jefe"), bytes_of("what do ya want for nothing?")) ==
        "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  CHECK(hmac_hex(std::vector<std::uint8_t>(20, 0xaa), std::vector<std::uint8_t>(50, 0xdd)) ==
        "773ea91e36800e46854db8ebd09181a72959098b3ef8c122d9635514ced565fe");
  CHECK(hmac_hex(from_hex("0102030405060708090a0b0c0d0e0f10111213141516171819"),
                 std::vector<std::uint8_t>(50, 0xcd)) ==
        "82558a389a443c0ea4cc819899f2083a85f0faa3e578f8077a2e3ff46729665b");
  // Case 5: the RFC gives only the first 128 bits.
  CHECK(hmac_hex(std::vector<std::uint8_t>(20, 0x0c), bytes_of("Test With Truncation")).substr(0, 32) ==
        "a3b6167473100ee06e0c796c2955552b");
  CHECK(hmac_hex(std::vector<std::uint8_t>(131, 0xaa),
                 bytes_of("Test Using Larger Than Block-Size Key - Hash Key First")) ==
        "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
  CHECK(hmac_hex(std::vector<std::uint8_t>(131, 0xaa),
                 bytes_of("This is a test using a larger than block-size key and a larger than block-size "
                          "data. The key needs to be hashed before being used by the HMAC algorithm.")) ==
        "9b09ffa71b942fcb27635fbcd5b0e944bfdc63644f0713938a7f51535c3a35e2");
}

TEST_CASE("HMAC-SHA-256: a prepared key gives the same tag for every message split") {
  const itp::crypto::HmacKey key(bytes_of("Jefe"));
  const auto msg = bytes_of("what do ya want for nothing?");
  for (std::size_t cut = 0; cut <= msg.size(); ++cut) {
    itp::crypto::Hmac mac(key);
    mac.update(std::span<const std::uint8_t>(msg.data(), cut));
    mac.update(std::span<const std::uint8_t>(msg.data() + cut, msg.size() - cut));
    CHECK(to_hex(mac.finish()) == "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  }
}
