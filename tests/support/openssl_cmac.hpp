#pragma once
// The tests' independent AES-128-CMAC: OpenSSL 3's EVP_MAC "CMAC" with cipher
// AES-128-CBC (RFC 4493), for checking ours (crypto) and the secure channel's
// derived keys and tags (link). Test-only; links OpenSSL::Crypto.
#include <doctest/doctest.h>
#include <openssl/core_names.h>
#include <openssl/evp.h>
#include <openssl/params.h>

#include <array>
#include <cstddef>
#include <cstdint>

namespace itp_test {

inline std::array<std::uint8_t, 16> openssl_cmac(const std::uint8_t* key, const std::uint8_t* msg,
                                                 std::size_t msg_size) {
  EVP_MAC* mac = EVP_MAC_fetch(nullptr, "CMAC", nullptr);
  REQUIRE(mac != nullptr);
  EVP_MAC_CTX* ctx = EVP_MAC_CTX_new(mac);
  REQUIRE(ctx != nullptr);
  char cipher[] = "AES-128-CBC";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_CIPHER, cipher, 0),
                               OSSL_PARAM_construct_end()};
  REQUIRE(EVP_MAC_init(ctx, key, 16, params) == 1);
  REQUIRE(EVP_MAC_update(ctx, msg, msg_size) == 1);
  std::array<std::uint8_t, 16> tag{};
  std::size_t len = 0;
  REQUIRE(EVP_MAC_final(ctx, tag.data(), &len, tag.size()) == 1);
  REQUIRE(len == 16);
  EVP_MAC_CTX_free(ctx);
  EVP_MAC_free(mac);
  return tag;
}

}  // namespace itp_test
