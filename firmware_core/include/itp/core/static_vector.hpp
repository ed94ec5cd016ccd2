#pragma once
// A vector with its capacity fixed at compile time and its storage inline.
// push_back reports a full vector instead of growing; it never allocates.
//
// As ETL's ivector: every StaticVector<T, N> is a VectorBase<T>, which holds
// the element pointer, size and capacity and offers the whole interface
// without N. Code that fills a container it does not own takes a
// VectorBase<T>& and is an ordinary function, not a template on N. The
// derived class owns the storage; copying one re-points the copy's base at
// the copy's own storage.
#include <cstddef>
#include <span>
#include <type_traits>

#include "itp/core/assert.hpp"

namespace itp {

template <typename T>
class VectorBase {
  static_assert(std::is_trivially_destructible_v<T>,
                "StaticVector holds plain data; elements are never destroyed");

 public:
  using value_type = T;

  VectorBase(const VectorBase&) = delete;  // a base alone owns no storage
  VectorBase& operator=(const VectorBase& other) {
    assign(other);
    return *this;
  }

  constexpr std::size_t size() const { return size_; }
  constexpr std::size_t capacity() const { return capacity_; }
  constexpr bool empty() const { return size_ == 0; }
  constexpr bool full() const { return size_ == capacity_; }
  constexpr void clear() { size_ = 0; }

  // Returns false (and changes nothing) when the vector is full.
  [[nodiscard]] constexpr bool push_back(const T& value) {
    if (size_ == capacity_) {
      return false;
    }
    data_[size_++] = value;
    return true;
  }

  constexpr void pop_back() {
    ITP_EXPECTS(size_ > 0);
    --size_;
  }

  // Shrinks, or grows with value-initialised elements; false if n > capacity.
  [[nodiscard]] constexpr bool resize(std::size_t n) {
    if (n > capacity_) {
      return false;
    }
    for (std::size_t i = size_; i < n; ++i) {  // bounded by the capacity
      data_[i] = T{};
    }
    size_ = n;
    return true;
  }

  // Copies the elements of `other`; false (and a copy cut to the capacity)
  // when they do not fit.
  constexpr bool assign(const VectorBase& other) {
    if (&other == this) {
      return true;
    }
    const std::size_t n = other.size_ < capacity_ ? other.size_ : capacity_;
    for (std::size_t i = 0; i < n; ++i) {  // bounded by the capacity
      data_[i] = other.data_[i];
    }
    size_ = n;
    return n == other.size_;
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

  constexpr T* data() { return data_; }
  constexpr const T* data() const { return data_; }
  constexpr T* begin() { return data_; }
  constexpr T* end() { return data_ + size_; }
  constexpr const T* begin() const { return data_; }
  constexpr const T* end() const { return data_ + size_; }

  constexpr std::span<T> span() { return {data_, size_}; }
  constexpr std::span<const T> span() const { return {data_, size_}; }

 protected:
  constexpr VectorBase(T* data, std::size_t capacity) : data_(data), capacity_(capacity) {}
  ~VectorBase() = default;

 private:
  T* data_;
  std::size_t size_ = 0;
  std::size_t capacity_;
};

template <typename T, std::size_t N>
class StaticVector : public VectorBase<T> {
 public:
  static constexpr std::size_t kCapacity = N;

  constexpr StaticVector() : VectorBase<T>(storage_, N) {}
  constexpr StaticVector(const StaticVector& other) : VectorBase<T>(storage_, N) {
    static_cast<void>(this->assign(other));  // same capacity: always fits
  }
  constexpr StaticVector& operator=(const StaticVector& other) {
    static_cast<void>(this->assign(other));  // same capacity: always fits
    return *this;
  }
  ~StaticVector() = default;

  static constexpr std::size_t capacity() { return N; }

 private:
  T storage_[N > 0 ? N : 1]{};  // one element for N = 0 (never used: capacity 0)
};

}  // namespace itp
