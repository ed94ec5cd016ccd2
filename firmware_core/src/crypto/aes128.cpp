#include "itp/crypto/aes128.hpp"

#include <bit>

#include "itp/crypto/constant_time.hpp"

namespace itp::crypto {
namespace {

// Gathers bits 0, 8, 16, 24 of v (one per row of a column) into bits 21..24:
// the four partial products v_r * 2^(8r + 7k) never overlap, so there are no
// carries (and a 32-bit multiply takes one cycle whatever its operands on the
// Cortex-M7).
constexpr std::uint32_t kGather = 0x00204081u;  // 1 + 2^7 + 2^14 + 2^21
constexpr std::uint32_t kEveryByte = 0x01010101u;

std::uint32_t load_le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// ShiftRows: row r of the state (bits r, r+4, r+8, r+12 of a plane) turns
// left by r columns, i.e. the bit pattern rotates right by 4r.
std::uint32_t shift_rows(std::uint32_t x) {
  return (x & 0x11111111u) | std::rotr(x & 0x22222222u, 4) | std::rotr(x & 0x44444444u, 8) |
         std::rotr(x & 0x88888888u, 12);
}

// Within each column (a nibble), row r takes row r+1's bit (r+2's for up2).
std::uint32_t rows_up1(std::uint32_t x) { return ((x >> 1) & 0x77777777u) | ((x << 3) & 0x88888888u); }
std::uint32_t rows_up2(std::uint32_t x) { return ((x >> 2) & 0x33333333u) | ((x << 2) & 0xCCCCCCCCu); }

// MixColumns: s'_r = 2 s_r + 3 s_{r+1} + s_{r+2} + s_{r+3}
//                  = 2 (s_r + s_{r+1}) + s_{r+1} + (s_{r+2} + s_{r+3}),
// with t = s + up1(s), the last term is up2(t). Multiplying the planes of t
// by 2 in GF(2^8) moves plane b to b+1 and folds plane 7 into planes
// 0, 1, 3, 4 (the reduction polynomial 0x11B).
void mix_columns(std::array<std::uint32_t, 8>& q) {
  std::array<std::uint32_t, 8> up1{};
  std::array<std::uint32_t, 8> t{};
  for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
    up1[b] = rows_up1(q[b]);
    t[b] = q[b] ^ up1[b];
  }
  const std::uint32_t top = t[7];
  q[0] = top ^ up1[0] ^ rows_up2(t[0]);
  q[1] = t[0] ^ top ^ up1[1] ^ rows_up2(t[1]);
  q[2] = t[1] ^ up1[2] ^ rows_up2(t[2]);
  q[3] = t[2] ^ top ^ up1[3] ^ rows_up2(t[3]);
  q[4] = t[3] ^ top ^ up1[4] ^ rows_up2(t[4]);
  q[5] = t[4] ^ up1[5] ^ rows_up2(t[5]);
  q[6] = t[5] ^ up1[6] ^ rows_up2(t[6]);
  q[7] = t[6] ^ up1[7] ^ rows_up2(t[7]);
}

void add_round_key(std::array<std::uint32_t, 8>& q, const std::array<std::uint16_t, 8>& k) {
  for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
    const std::uint32_t kb = k[b];
    q[b] ^= kb | (kb << 16);
  }
}

}  // namespace

// The S-box as a Boolean circuit: J. Boyar and R. Peralta, "A new combinational
// logic minimization technique with applications to cryptology" (SEA 2010),
// 113 gates: a linear top layer (23 XOR), a non-linear middle (GF(2^4)
// inversion in a tower field, 32 AND, 30 XOR) and a linear bottom layer with
// the affine map (30 XOR, 4 XNOR). In the paper's notation U0 is the most
// significant input bit and S0 the most significant output bit.
namespace {

// Inlined into the rounds (the planes stay in registers as far as they fit).
[[gnu::always_inline]] inline void sub_bytes(std::array<std::uint32_t, 8>& planes) {
  const std::uint32_t u0 = planes[7], u1 = planes[6], u2 = planes[5], u3 = planes[4];
  const std::uint32_t u4 = planes[3], u5 = planes[2], u6 = planes[1], u7 = planes[0];

  // Top linear layer.
  const std::uint32_t t1 = u0 ^ u3;
  const std::uint32_t t2 = u0 ^ u5;
  const std::uint32_t t3 = u0 ^ u6;
  const std::uint32_t t4 = u3 ^ u5;
  const std::uint32_t t5 = u4 ^ u6;
  const std::uint32_t t6 = t1 ^ t5;
  const std::uint32_t t7 = u1 ^ u2;
  const std::uint32_t t8 = u7 ^ t6;
  const std::uint32_t t9 = u7 ^ t7;
  const std::uint32_t t10 = t6 ^ t7;
  const std::uint32_t t11 = u1 ^ u5;
  const std::uint32_t t12 = u2 ^ u5;
  const std::uint32_t t13 = t3 ^ t4;
  const std::uint32_t t14 = t6 ^ t11;
  const std::uint32_t t15 = t5 ^ t11;
  const std::uint32_t t16 = t5 ^ t12;
  const std::uint32_t t17 = t9 ^ t16;
  const std::uint32_t t18 = u3 ^ u7;
  const std::uint32_t t19 = t7 ^ t18;
  const std::uint32_t t20 = t1 ^ t19;
  const std::uint32_t t21 = u6 ^ u7;
  const std::uint32_t t22 = t7 ^ t21;
  const std::uint32_t t23 = t2 ^ t22;
  const std::uint32_t t24 = t2 ^ t10;
  const std::uint32_t t25 = t20 ^ t17;
  const std::uint32_t t26 = t3 ^ t16;
  const std::uint32_t t27 = t1 ^ t12;

  // Non-linear middle.
  const std::uint32_t m1 = t13 & t6;
  const std::uint32_t m2 = t23 & t8;
  const std::uint32_t m3 = t14 ^ m1;
  const std::uint32_t m4 = t19 & u7;
  const std::uint32_t m5 = m4 ^ m1;
  const std::uint32_t m6 = t3 & t16;
  const std::uint32_t m7 = t22 & t9;
  const std::uint32_t m8 = t26 ^ m6;
  const std::uint32_t m9 = t20 & t17;
  const std::uint32_t m10 = m9 ^ m6;
  const std::uint32_t m11 = t1 & t15;
  const std::uint32_t m12 = t4 & t27;
  const std::uint32_t m13 = m12 ^ m11;
  const std::uint32_t m14 = t2 & t10;
  const std::uint32_t m15 = m14 ^ m11;
  const std::uint32_t m16 = m3 ^ m2;
  const std::uint32_t m17 = m5 ^ t24;
  const std::uint32_t m18 = m8 ^ m7;
  const std::uint32_t m19 = m10 ^ m15;
  const std::uint32_t m20 = m16 ^ m13;
  const std::uint32_t m21 = m17 ^ m15;
  const std::uint32_t m22 = m18 ^ m13;
  const std::uint32_t m23 = m19 ^ t25;
  const std::uint32_t m24 = m22 ^ m23;
  const std::uint32_t m25 = m22 & m20;
  const std::uint32_t m26 = m21 ^ m25;
  const std::uint32_t m27 = m20 ^ m21;
  const std::uint32_t m28 = m23 ^ m25;
  const std::uint32_t m29 = m28 & m27;
  const std::uint32_t m30 = m26 & m24;
  const std::uint32_t m31 = m20 & m23;
  const std::uint32_t m32 = m27 & m31;
  const std::uint32_t m33 = m27 ^ m25;
  const std::uint32_t m34 = m21 & m22;
  const std::uint32_t m35 = m24 & m34;
  const std::uint32_t m36 = m24 ^ m25;
  const std::uint32_t m37 = m21 ^ m29;
  const std::uint32_t m38 = m32 ^ m33;
  const std::uint32_t m39 = m23 ^ m30;
  const std::uint32_t m40 = m35 ^ m36;
  const std::uint32_t m41 = m38 ^ m40;
  const std::uint32_t m42 = m37 ^ m39;
  const std::uint32_t m43 = m37 ^ m38;
  const std::uint32_t m44 = m39 ^ m40;
  const std::uint32_t m45 = m42 ^ m41;
  const std::uint32_t m46 = m44 & t6;
  const std::uint32_t m47 = m40 & t8;
  const std::uint32_t m48 = m39 & u7;
  const std::uint32_t m49 = m43 & t16;
  const std::uint32_t m50 = m38 & t9;
  const std::uint32_t m51 = m37 & t17;
  const std::uint32_t m52 = m42 & t15;
  const std::uint32_t m53 = m45 & t27;
  const std::uint32_t m54 = m41 & t10;
  const std::uint32_t m55 = m44 & t13;
  const std::uint32_t m56 = m40 & t23;
  const std::uint32_t m57 = m39 & t19;
  const std::uint32_t m58 = m43 & t3;
  const std::uint32_t m59 = m38 & t22;
  const std::uint32_t m60 = m37 & t20;
  const std::uint32_t m61 = m42 & t1;
  const std::uint32_t m62 = m45 & t4;
  const std::uint32_t m63 = m41 & t2;

  // Bottom linear layer (with the affine constant 0x63 as the four XNORs).
  const std::uint32_t l0 = m61 ^ m62;
  const std::uint32_t l1 = m50 ^ m56;
  const std::uint32_t l2 = m46 ^ m48;
  const std::uint32_t l3 = m47 ^ m55;
  const std::uint32_t l4 = m54 ^ m58;
  const std::uint32_t l5 = m49 ^ m61;
  const std::uint32_t l6 = m62 ^ l5;
  const std::uint32_t l7 = m46 ^ l3;
  const std::uint32_t l8 = m51 ^ m59;
  const std::uint32_t l9 = m52 ^ m53;
  const std::uint32_t l10 = m53 ^ l4;
  const std::uint32_t l11 = m60 ^ l2;
  const std::uint32_t l12 = m48 ^ m51;
  const std::uint32_t l13 = m50 ^ l0;
  const std::uint32_t l14 = m52 ^ m61;
  const std::uint32_t l15 = m55 ^ l1;
  const std::uint32_t l16 = m56 ^ l0;
  const std::uint32_t l17 = m57 ^ l1;
  const std::uint32_t l18 = m58 ^ l8;
  const std::uint32_t l19 = m63 ^ l4;
  const std::uint32_t l20 = l0 ^ l1;
  const std::uint32_t l21 = l1 ^ l7;
  const std::uint32_t l22 = l3 ^ l12;
  const std::uint32_t l23 = l18 ^ l2;
  const std::uint32_t l24 = l15 ^ l9;
  const std::uint32_t l25 = l6 ^ l10;
  const std::uint32_t l26 = l7 ^ l9;
  const std::uint32_t l27 = l8 ^ l10;
  const std::uint32_t l28 = l11 ^ l14;
  const std::uint32_t l29 = l11 ^ l17;

  planes[7] = l6 ^ l24;     // S0
  planes[6] = ~(l16 ^ l26);  // S1
  planes[5] = ~(l19 ^ l28);  // S2
  planes[4] = l6 ^ l21;     // S3
  planes[3] = l20 ^ l22;    // S4
  planes[2] = l25 ^ l29;    // S5
  planes[1] = ~(l13 ^ l27);  // S6
  planes[0] = ~(l6 ^ l23);   // S7
}

}  // namespace

void aes_sub_bytes_planes(std::array<std::uint32_t, 8>& planes) { sub_bytes(planes); }

AesPlanes AesPlanes::load(std::span<const std::uint8_t, kAesBlockBytes> bytes) {
  // Column c is input bytes 4c..4c+3 (rows 0..3), read as one little-endian
  // word: bit b of row r at bit 8r + b. Plane b takes those four bits as the
  // nibble of column c.
  std::array<std::uint32_t, 4> col{};
  for (std::size_t c = 0; c < 4; ++c) {  // 4 columns
    col[c] = load_le32(bytes.data() + 4 * c);
  }
  AesPlanes s;
  for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
    std::uint32_t p = 0;
    for (std::size_t c = 0; c < 4; ++c) {  // 4 columns
      const std::uint32_t bits = (col[c] >> b) & kEveryByte;
      p |= (((bits * kGather) >> 21) & 0xFu) << (4 * c);
    }
    s.plane[b] = p | (p << 16);
  }
  return s;
}

void AesPlanes::store(std::span<std::uint8_t, kAesBlockBytes> bytes) const {
  std::array<std::uint32_t, 4> col{};
  for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
    for (std::size_t c = 0; c < 4; ++c) {  // 4 columns
      // The nibble's bit r goes to bit 8r (products r + 7k never overlap).
      const std::uint32_t nibble = (plane[b] >> (4 * c)) & 0xFu;
      col[c] |= ((nibble * kGather) & kEveryByte) << b;
    }
  }
  for (std::size_t c = 0; c < 4; ++c) {  // 4 columns
    for (std::size_t r = 0; r < 4; ++r) {  // 4 rows
      bytes[4 * c + r] = static_cast<std::uint8_t>(col[c] >> (8 * r));
    }
  }
  secure_wipe(col.data(), sizeof(col));
}

void Aes128::set_key(std::span<const std::uint8_t, kAes128KeyBytes> key) {
  // FIPS 197, 5.2: 44 words w[i]; w[i] = w[i-4] ^ (i % 4 == 0 ?
  // SubWord(RotWord(w[i-1])) ^ Rcon[i/4] : w[i-1]). The round constants are
  // indexed by the public round number; SubWord runs the S-box circuit on
  // four bit positions, so no step looks anything up by key bytes.
  constexpr std::array<std::uint8_t, kAes128Rounds> kRcon = {0x01, 0x02, 0x04, 0x08, 0x10,
                                                             0x20, 0x40, 0x80, 0x1B, 0x36};
  std::array<std::uint8_t, kAesBlockBytes> rk{};
  for (std::size_t i = 0; i < kAesBlockBytes; ++i) {  // 16 bytes
    rk[i] = key[i];
  }
  std::array<std::uint32_t, 8> word{};
  for (std::size_t round = 0; round <= kAes128Rounds; ++round) {  // 11 round keys
    if (round > 0) {
      // RotWord of the last word (bytes 12..15) into bit positions 0..3.
      word.fill(0u);
      for (std::size_t t = 0; t < 4; ++t) {  // 4 bytes
        const std::uint8_t byte = rk[12 + ((t + 1) % 4)];
        for (std::size_t b = 0; b < 8; ++b) {  // 8 bits
          word[b] |= static_cast<std::uint32_t>((byte >> b) & 1u) << t;
        }
      }
      aes_sub_bytes_planes(word);
      std::array<std::uint8_t, 4> sub{};
      for (std::size_t t = 0; t < 4; ++t) {  // 4 bytes
        std::uint32_t v = 0;
        for (std::size_t b = 0; b < 8; ++b) {  // 8 bits
          v |= ((word[b] >> t) & 1u) << b;
        }
        sub[t] = static_cast<std::uint8_t>(v);
      }
      sub[0] = static_cast<std::uint8_t>(sub[0] ^ kRcon[round - 1]);
      for (std::size_t t = 0; t < 4; ++t) {  // w[4k] = w[4k-4] ^ temp
        rk[t] = static_cast<std::uint8_t>(rk[t] ^ sub[t]);
      }
      for (std::size_t i = 4; i < kAesBlockBytes; ++i) {  // w[4k+j] = w[4k+j-4] ^ w[4k+j-1]
        rk[i] = static_cast<std::uint8_t>(rk[i] ^ rk[i - 4]);
      }
      secure_wipe(sub.data(), sizeof(sub));
    }
    const AesPlanes planes = AesPlanes::load(rk);
    for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
      round_keys_[round][b] = static_cast<std::uint16_t>(planes.plane[b] & 0xFFFFu);
    }
  }
  secure_wipe(rk.data(), sizeof(rk));
  secure_wipe(word.data(), sizeof(word));
}

void Aes128::wipe() { secure_wipe(round_keys_.data(), sizeof(round_keys_)); }

void Aes128::encrypt(AesPlanes& state) const {
  std::array<std::uint32_t, 8>& q = state.plane;
  add_round_key(q, round_keys_[0]);
  for (std::size_t round = 1; round <= kAes128Rounds; ++round) {  // 10 rounds
    sub_bytes(q);
    for (std::size_t b = 0; b < 8; ++b) {  // 8 planes
      q[b] = shift_rows(q[b]);
    }
    if (round < kAes128Rounds) {  // public: the last round has no MixColumns
      mix_columns(q);
    }
    add_round_key(q, round_keys_[round]);
  }
}

void Aes128::encrypt(std::span<const std::uint8_t, kAesBlockBytes> in,
                     std::span<std::uint8_t, kAesBlockBytes> out) const {
  AesPlanes s = AesPlanes::load(in);
  encrypt(s);
  s.store(out);
  secure_wipe(s.plane.data(), sizeof(s.plane));
}

}  // namespace itp::crypto
