#pragma once
// The instruction set the vector kernels run on, chosen when a run starts:
// AVX2 where the processor has it, else the portable kernels (SSE2, the
// x86-64 baseline). A kernel written on Lanes<L> (lanes.hpp) is
// instantiated for both lane counts and both dimensions; run_vector_kernel
// calls the one chosen, kernel.template operator()<D, L>(): L = 4 on AVX2,
// 2 otherwise. The lambda must call the kernel directly (no function
// pointer) and the kernel be always inlined: the AVX2 copy exists only where
// it is inlined into run_avx2, built for AVX2. The build fuses no
// multiply-add (-ffp-contract=off), so one binary runs on any x86-64 machine
// and rounds the same on every one of them.
#include <string>

namespace suffuse::detail {

enum class KernelIsa { portable, avx2 };

// AVX2 if the processor has it; the environment variable SUFFUSE_KERNELS
// (auto, the same as empty; portable; avx2) overrides, to compare the two.
// Throws Error on another value, or on avx2 where the processor lacks it.
KernelIsa kernel_isa_for_this_machine();
std::string kernel_isa_name(KernelIsa isa);

// SUFFUSE_PORTABLE_KERNELS_ONLY: no AVX2 copies (the sanitized build).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(SUFFUSE_PORTABLE_KERNELS_ONLY)
#define SUFFUSE_HAS_AVX2_KERNELS 1
template <class Kernel>
__attribute__((target("avx2"), flatten)) void run_avx2(int dim, const Kernel& kernel) {
  if (dim == 2)
    kernel.template operator()<2, 4>();
  else
    kernel.template operator()<3, 4>();
}
#endif

template <class Kernel>
void run_vector_kernel(KernelIsa isa, int dim, const Kernel& kernel) {
#ifdef SUFFUSE_HAS_AVX2_KERNELS
  if (isa == KernelIsa::avx2) {
    run_avx2(dim, kernel);
    return;
  }
#endif
  (void)isa;
  if (dim == 2)
    kernel.template operator()<2, 2>();
  else
    kernel.template operator()<3, 2>();
}

}  // namespace suffuse::detail
