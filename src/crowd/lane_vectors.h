// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// The lane vectors of the crowd's 8-instance loops (cull_lanes.h, record_lanes.h): GCC and
// Clang vector extensions where the compiler has them, else (MSVC, or SI_PORTABLE_LANES defined,
// as CMake's -DSI_PORTABLE_LANES=ON does) a plain array per vector with the same operators, which
// computes lane by lane exactly the same float operations, so both select and write the same.
//
// What the lane code uses, in both:
// - LaneVector<T, N>: N lanes of T with + - * (also with a scalar), the comparisons (a mask:
//   every bit set where true, the integer type of T's width), & | ~ on integer lanes, += -=;
// - loadLanes(at, a, pa, b, pb, ...): each vector loaded from its array;
// - SI_LANES_CAST(Type, v): the same bits as another lane type of the same width;
// - SI_LANES_CONVERT(v, Type): each lane converted (as static_cast, truncating toward zero);
// - SI_LANES_INLINE: always inlined (the vector types never cross a call);
// - SI_LANES_NAMESPACE: an inline namespace named after the kind (vector_extensions or
//   portable), so that code built with each kind (the portable lanes' own test, beside the
//   library) never shares a symbol.

#include <cstdint>
#include <cstring>

#if (defined(__GNUC__) || defined(__clang__)) && !defined(SI_PORTABLE_LANES)
#define SI_LANES_EXTENSIONS 1
#define SI_LANES_INLINE __attribute__((always_inline)) inline
#define SI_LANES_NAMESPACE vector_extensions
#else
#define SI_LANES_EXTENSIONS 0
#if defined(_MSC_VER)
#define SI_LANES_INLINE __forceinline
#else
#define SI_LANES_INLINE inline
#endif
#define SI_LANES_NAMESPACE portable
#endif

namespace si::lanes {
inline namespace SI_LANES_NAMESPACE {

#if SI_LANES_EXTENSIONS

template <typename T, int N>
struct VectorOf {
  typedef T type __attribute__((vector_size(sizeof(T) * N)));
};
template <typename T, int N>
using LaneVector = typename VectorOf<T, N>::type;
#define SI_LANES_CAST(Type, v) ((Type)(v))
#define SI_LANES_CONVERT(v, Type) __builtin_convertvector((v), Type)

#else

/// The integer lane type of T's width: what comparisons give.
template <size_t Bytes>
struct MaskLane;
template <>
struct MaskLane<4> {
  using type = int32_t;
};
template <>
struct MaskLane<8> {
  using type = int64_t;
};

template <typename T, int N>
struct LaneVector {
  using value_type = T;
  static constexpr int kLanes = N;
  using Mask = LaneVector<typename MaskLane<sizeof(T)>::type, N>;
  T v[N];

  T& operator[](int k) { return v[k]; }
  const T& operator[](int k) const { return v[k]; }

  // Lane by lane: each lane of `a op b` converted by `lane` into a lane of Result (T itself,
  // or a mask lane), with a scalar on either side too.
  static typename MaskLane<sizeof(T)>::type maskLane(bool x) { return x ? -1 : 0; }
#define SI_LANES_OP(op, Result, lane)                                   \
  friend Result operator op(const LaneVector& a, const LaneVector& b) { \
    Result r;                                                           \
    for (int k = 0; k < N; ++k) r.v[k] = lane(a.v[k] op b.v[k]);        \
    return r;                                                           \
  }                                                                     \
  friend Result operator op(const LaneVector& a, T b) {                 \
    return a op splat(b);                                               \
  }                                                                     \
  friend Result operator op(T a, const LaneVector& b) {                 \
    return splat(a) op b;                                               \
  }
#define SI_LANES_BINARY(op)                         \
  SI_LANES_OP(op, LaneVector, T)                    \
  LaneVector& operator op##=(const LaneVector& b) { \
    return *this = *this op b;                      \
  }
  SI_LANES_BINARY(+)
  SI_LANES_BINARY(-)
  SI_LANES_BINARY(*)
  SI_LANES_BINARY(&)
  SI_LANES_BINARY(|)
#undef SI_LANES_BINARY
#define SI_LANES_UNARY(op)                             \
  friend LaneVector operator op(const LaneVector& a) { \
    LaneVector r;                                      \
    for (int k = 0; k < N; ++k) r.v[k] = T(op a.v[k]); \
    return r;                                          \
  }
  SI_LANES_UNARY(~)
  SI_LANES_UNARY(-)
#undef SI_LANES_UNARY
#define SI_LANES_COMPARE(op) SI_LANES_OP(op, Mask, maskLane)
  SI_LANES_COMPARE(<)
  SI_LANES_COMPARE(<=)
  SI_LANES_COMPARE(>)
  SI_LANES_COMPARE(>=)
  SI_LANES_COMPARE(==)
#undef SI_LANES_COMPARE
#undef SI_LANES_OP

  static LaneVector splat(T x) {
    LaneVector r;
    for (int k = 0; k < N; ++k) r.v[k] = x;
    return r;
  }
};

/// The same bits as lane type `To` (of the same width).
template <typename To, typename From>
To laneCast(const From& from) {
  static_assert(sizeof(To) == sizeof(From), "lane casts keep the width");
  To to;
  std::memcpy(&to, &from, sizeof to);
  return to;
}
/// Each lane converted as static_cast does (truncating toward zero).
template <typename To, typename From>
To laneConvert(const From& from) {
  static_assert(To::kLanes == From::kLanes, "lane conversions keep the lane count");
  To to;
  for (int k = 0; k < To::kLanes; ++k) to.v[k] = static_cast<typename To::value_type>(from.v[k]);
  return to;
}
#define SI_LANES_CAST(Type, v) (::si::lanes::laneCast<Type>(v))
#define SI_LANES_CONVERT(v, Type) (::si::lanes::laneConvert<Type>(v))

#endif

/// Loads each lane vector from its array, from element `at` on: loadLanes(at, a, pa, b, pb, ...)
/// copies pa[at...] into a, pb[at...] into b, and so on.
template <typename V, typename E, typename... Rest>
SI_LANES_INLINE void loadLanes(uint32_t at, V& dst, const E* src, Rest&&... rest) {
  std::memcpy(&dst, src + at, sizeof dst);
  if constexpr (sizeof...(Rest) > 0) loadLanes(at, static_cast<Rest&&>(rest)...);
}

}  // namespace SI_LANES_NAMESPACE
}  // namespace si::lanes
