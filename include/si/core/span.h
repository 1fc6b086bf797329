// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// A minimal non-owning view of contiguous elements, as C++20's std::span (the library is C++17).
/// Inputs are `Span<const T>`, outputs `Span<T>`; the caller owns the memory.

#include <array>
#include <cassert>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace si {

/// A pointer and an element count. Never owns; never allocates.
template <typename T>
class Span {
 public:
  using element_type = T;
  using value_type = std::remove_cv_t<T>;

  constexpr Span() = default;
  /// Views `count` elements starting at `data` (`data` may be null only when `count` is 0).
  constexpr Span(T* data, size_t count) : data_(data), count_(count) {}
  /// Views a whole vector.
  template <typename U, typename A,
            typename = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  Span(std::vector<U, A>& v) : data_(v.data()), count_(v.size()) {}  // NOLINT: implicit by design
  /// Views a whole const vector (only for `Span<const T>`).
  template <typename U, typename A,
            typename = std::enable_if_t<std::is_convertible_v<const U (*)[], T (*)[]>>>
  Span(const std::vector<U, A>& v) : data_(v.data()), count_(v.size()) {}  // NOLINT
  /// Views a whole array.
  template <typename U, size_t N, typename = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  constexpr Span(std::array<U, N>& a) : data_(a.data()), count_(N) {}  // NOLINT
  template <typename U, size_t N,
            typename = std::enable_if_t<std::is_convertible_v<const U (*)[], T (*)[]>>>
  constexpr Span(const std::array<U, N>& a) : data_(a.data()), count_(N) {}  // NOLINT
  template <size_t N>
  constexpr Span(T (&a)[N]) : data_(a), count_(N) {}  // NOLINT
  /// A `Span<T>` converts to a `Span<const T>`.
  template <typename U, typename = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
  constexpr Span(Span<U> other) : data_(other.data()), count_(other.size()) {}  // NOLINT

  constexpr T* data() const { return data_; }
  constexpr size_t size() const { return count_; }
  constexpr size_t size_bytes() const { return count_ * sizeof(T); }
  constexpr bool empty() const { return count_ == 0; }
  constexpr T* begin() const { return data_; }
  constexpr T* end() const { return data_ + count_; }
  /// Element `i`; `i` must be below size() (asserted in debug builds).
  constexpr T& operator[](size_t i) const {
    assert(i < count_ && "si::Span index out of range");
    return data_[i];
  }
  /// The `count` elements starting at `offset`; the range must lie inside the span.
  constexpr Span subspan(size_t offset, size_t count) const {
    assert(offset <= count_ && count <= count_ - offset && "si::Span::subspan out of range");
    return Span(data_ + offset, count);
  }

 private:
  T* data_ = nullptr;
  size_t count_ = 0;
};

}  // namespace si
