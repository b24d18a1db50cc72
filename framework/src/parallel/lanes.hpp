#pragma once
// L doubles as one value (GCC's vector extension), for the sums of one
// node's block. Kernels take L as a template parameter: 2 on the portable
// x86-64 baseline (SSE2), 4 where they are built for AVX2 (kernel_isa.hpp).
// Each lane is rounded exactly as the scalar operation it replaces (no fused
// multiply-add: the build contracts none, -ffp-contract=off), so results do
// not depend on the instruction set. The kernels and these helpers are
// always inlined: an AVX2 copy exists only where it is inlined into the
// function built for AVX2 (clang's flatten inlines one level only).
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <utility>

namespace suffuse::detail {

template <int L>
struct LaneType;
template <>
struct LaneType<1> {
  using type = double;
};
template <>
struct LaneType<2> {
  typedef double type __attribute__((vector_size(2 * sizeof(double))));
};
template <>
struct LaneType<4> {
  typedef double type __attribute__((vector_size(4 * sizeof(double))));
};
template <int L>
using Lanes = typename LaneType<L>::type;

// Lanes from values in a local array, element by element, so that the array
// can live in registers (a vector load of freshly stored scalars would stall
// on store forwarding).
template <int L, std::size_t... I>
[[gnu::always_inline]] inline Lanes<L> gather_lanes(const double* a, std::index_sequence<I...>) {
  return Lanes<L>{a[I]...};
}
template <int L>
[[gnu::always_inline]] inline Lanes<L> lanes_of(const double* a) {
  return gather_lanes<L>(a, std::make_index_sequence<L>());
}

template <int L>
[[gnu::always_inline]] inline Lanes<L> load_lanes(const double* p) {
  Lanes<L> v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <int L>
[[gnu::always_inline]] inline void add_lanes(double* p, Lanes<L> v) {
  const Lanes<L> sum = load_lanes<L>(p) + v;
  std::memcpy(p, &sum, sizeof sum);
}

// The lanes for a block of W values on an instruction set of L lanes: L if
// they divide W, else two (W even) or one.
template <int W, int L>
inline constexpr int block_lanes = W % L == 0 ? L : W % 2 == 0 ? 2 : 1;

// A point's W values, each to be added to a node's block times the node's
// weight: block[c] += N a[c].
template <int W, int L>
struct WeightedValues {
  static constexpr int lanes = block_lanes<W, L>, vectors = W / lanes;
  Lanes<lanes> a[vectors];
  [[gnu::always_inline]] explicit WeightedValues(const double* values) {
    for (int v = 0; v < vectors; ++v) a[v] = lanes_of<lanes>(values + v * lanes);
  }
  [[gnu::always_inline]] void add_to(double* block, double N) const {
    for (int v = 0; v < vectors; ++v) add_lanes<lanes>(block + v * lanes, a[v] * N);
  }
};

// W sums a gather forms from a node's contiguous values: sum += x[c] s for
// each node, in lanes where they fit (a D-vector in 3D: two lanes and one).
template <int W, int L>
struct WeightedSums {
  static constexpr int lanes = W % L == 0 ? L : W >= 2 ? 2 : 1, vectors = W / lanes, head = vectors * lanes;
  Lanes<lanes> v[vectors] = {};
  double tail[W - head + 1] = {};  // one more than needed: never empty
  [[gnu::always_inline]] void add(const double* x, double s) {
    for (int k = 0; k < vectors; ++k) v[k] += load_lanes<lanes>(x + k * lanes) * s;
    for (int c = head; c < W; ++c) tail[c - head] += x[c] * s;
  }
  double operator[](int c) const {
    if constexpr (lanes == 1)
      return v[c];
    else
      return c < head ? v[c / lanes][c % lanes] : tail[c - head];
  }
};

// Per-point operations written once for T = double and T = Lanes<L> (L
// points at a time), so that a kernel's body serves both its vector loop and
// its scalar tail, and every lane rounds as the scalar code does: the same
// operations in the same order (divisions and square roots are correctly
// rounded in either form), std::max's and std::min's choices, and selects
// where the scalar code branched (both sides are computed; the other is
// discarded, whatever it was).
template <class T>
inline constexpr int lane_count = sizeof(T) / sizeof(double);

template <class T>
[[gnu::always_inline]] inline T splat(double v) {
  return T{} + v;
}
template <class T>
[[gnu::always_inline]] inline T lane_max(T a, T b) {  // std::max(a, b)
  return a < b ? b : a;
}
template <class T>
[[gnu::always_inline]] inline T lane_min(T a, T b) {  // std::min(a, b)
  return b < a ? b : a;
}
// mask ? a : b lane by lane (mask: a comparison of two T).
template <class M, class T>
[[gnu::always_inline]] inline T pick(M mask, T a, T b) {
  return mask ? a : b;
}
template <class M>
[[gnu::always_inline]] inline bool any_lane(M mask) {
  if constexpr (std::is_same_v<M, bool>) {
    return mask;
  } else {
    for (std::size_t l = 0; l < sizeof(M) / sizeof(mask[0]); ++l)
      if (mask[l]) return true;
    return false;
  }
}
// The build sets -fno-math-errno, so this is one vector instruction.
template <class T>
[[gnu::always_inline]] inline T lane_sqrt(T x) {
  if constexpr (std::is_same_v<T, double>) {
    return std::sqrt(x);
  } else {
    for (int l = 0; l < lane_count<T>; ++l) x[l] = std::sqrt(x[l]);
    return x;
  }
}
// The values of lane_count<T> consecutive points at p (stride 1), or of one
// component of their vectors (stride S: p[0], p[S], ...); store_at writes them.
template <class T, int S = 1>
[[gnu::always_inline]] inline T load_at(const double* p) {
  if constexpr (std::is_same_v<T, double>) {
    return *p;
  } else if constexpr (S == 1) {
    return load_lanes<lane_count<T>>(p);
  } else {
    T v;
    for (int l = 0; l < lane_count<T>; ++l) v[l] = p[l * S];
    return v;
  }
}
template <class T, int S = 1>
[[gnu::always_inline]] inline void store_at(double* p, T v) {
  if constexpr (std::is_same_v<T, double>) {
    *p = v;
  } else if constexpr (S == 1) {
    std::memcpy(p, &v, sizeof v);
  } else {
    for (int l = 0; l < lane_count<T>; ++l) p[l * S] = v[l];
  }
}

// Calls body.template operator()<T>(p) for p in [begin, end): T = Lanes<L>
// on whole groups of L points, then T = double on the rest.
template <int L, class Body>
[[gnu::always_inline]] inline void for_points_in_lanes(std::size_t begin, std::size_t end, const Body& body) {
  std::size_t p = begin;
  if constexpr (L > 1)
    for (; p + L <= end; p += L) body.template operator()<Lanes<L>>(p);
  for (; p < end; ++p) body.template operator()<double>(p);
}

}  // namespace suffuse::detail
