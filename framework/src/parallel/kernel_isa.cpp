#include "parallel/kernel_isa.hpp"

#include <cstdlib>

#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace {
bool processor_has_avx2() {
#ifdef SUFFUSE_HAS_AVX2_KERNELS
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}
}  // namespace

KernelIsa kernel_isa_for_this_machine() {
  const char* chosen = std::getenv("SUFFUSE_KERNELS");
  const std::string value = chosen ? chosen : "";
  if (value == "portable") return KernelIsa::portable;
  if (value == "auto" || value.empty()) return processor_has_avx2() ? KernelIsa::avx2 : KernelIsa::portable;
  if (value == "avx2") {
    if (!processor_has_avx2()) throw Error("SUFFUSE_KERNELS=avx2, but this processor has no AVX2");
    return KernelIsa::avx2;
  }
  throw Error("SUFFUSE_KERNELS: expected auto, portable or avx2, found '" + value + "'");
}

std::string kernel_isa_name(KernelIsa isa) {
#ifdef SUFFUSE_HAS_AVX2_KERNELS
  return isa == KernelIsa::avx2 ? "avx2" : "portable (sse2)";
#else
  (void)isa;
  return "portable";
#endif
}

}  // namespace suffuse::detail
