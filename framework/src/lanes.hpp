#pragma once
// L doubles as one value (GCC's vector extension), for the sums of one
// node's block. Kernels take L as a template parameter: 2 on the portable
// x86-64 baseline (SSE2), 4 where they are built for AVX2 (kernel_isa.hpp).
// Each lane is rounded exactly as the scalar operation it replaces (no fused
// multiply-add: the build contracts none, -ffp-contract=off), so results do
// not depend on the instruction set. The kernels and these helpers are
// always inlined: an AVX2 copy exists only where it is inlined into the
// function built for AVX2 (clang's flatten inlines one level only).
#include <cstddef>
#include <cstring>
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

}  // namespace suffuse::detail
