// SHA-256 against the examples published with FIPS 180-2 (Appendix B) and
// the NIST example values: one block, two blocks, a million 'a', the empty
// message; and split updates give the same digest as one update.
#include <doctest/doctest.h>

#include <string>

#include "heap_guard.hpp"
#include "hex.hpp"
#include "itp/crypto/sha256.hpp"

using crypto_test::bytes_of;
using crypto_test::to_hex;
using itp::crypto::sha256;

TEST_CASE("SHA-256 of the FIPS 180-2 examples") {
  CHECK(to_hex(sha256(bytes_of("abc"))) ==
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(to_hex(sha256(bytes_of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"))) ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(to_hex(sha256(bytes_of(""))) ==
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  const std::string million(1000000, 'a');
  CHECK(to_hex(sha256(bytes_of(million))) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("SHA-256 gives the same digest however the message is split, without heap") {
  const auto msg = bytes_of("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrsmnopqrstnopqrstu");
  const std::string expected = "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1";
  for (std::size_t cut = 0; cut <= msg.size(); ++cut) {
    itp::crypto::Sha256 h;
    itp::crypto::Sha256Digest digest{};
    {
      test_support::HeapGuard guard;
      h.update(std::span<const std::uint8_t>(msg.data(), cut));
      for (std::size_t i = cut; i < msg.size(); ++i) {
        h.update(msg[i]);
      }
      digest = h.finish();
    }
    REQUIRE(to_hex(digest) == expected);
  }
}
