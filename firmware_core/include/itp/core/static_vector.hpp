#pragma once
// A vector with its capacity fixed at compile time and its storage inline.
// push_back reports a full vector instead of growing; it never allocates.
#include <array>
#include <cstddef>
#include <span>
#include <type_traits>

#include "itp/core/assert.hpp"

namespace itp {

template <typename T, std::size_t N>
class StaticVector {
  static_assert(std::is_trivially_destructible_v<T>,
                "StaticVector holds plain data; elements are never destroyed");

 public:
  using value_type = T;
  static constexpr std::size_t kCapacity = N;

  constexpr std::size_t size() const { return size_; }
  static constexpr std::size_t capacity() { return N; }
  constexpr bool empty() const { return size_ == 0; }
  constexpr bool full() const { return size_ == N; }
  constexpr void clear() { size_ = 0; }

  // Returns false (and changes nothing) when the vector is full.
  [[nodiscard]] constexpr bool push_back(const T& value) {
    if (size_ == N) {
      return false;
    }
    data_[size_++] = value;
    return true;
  }

  constexpr void pop_back() {
    ITP_EXPECTS(size_ > 0);
    --size_;
  }

  // Shrinks, or grows with value-initialised elements; false if n > N.
  [[nodiscard]] constexpr bool resize(std::size_t n) {
    if (n > N) {
      return false;
    }
    for (std::size_t i = size_; i < n; ++i) {  // bounded by N
      data_[i] = T{};
    }
    size_ = n;
    return true;
  }

  constexpr T& operator[](std::size_t i) {
    ITP_EXPECTS(i < size_);
    return data_[i];
  }
  constexpr const T& operator[](std::size_t i) const {
    ITP_EXPECTS(i < size_);
    return data_[i];
  }
  constexpr T& back() { return (*this)[size_ - 1]; }
  constexpr const T& back() const { return (*this)[size_ - 1]; }

  constexpr T* data() { return data_.data(); }
  constexpr const T* data() const { return data_.data(); }
  constexpr T* begin() { return data_.data(); }
  constexpr T* end() { return data_.data() + size_; }
  constexpr const T* begin() const { return data_.data(); }
  constexpr const T* end() const { return data_.data() + size_; }

  // Capacity-free views, so non-template code accepts any N.
  constexpr std::span<T> span() { return {data_.data(), size_}; }
  constexpr std::span<const T> span() const { return {data_.data(), size_}; }

 private:
  std::array<T, N> data_{};
  std::size_t size_ = 0;
};

}  // namespace itp
