#include "soccer_vision/segmentation/simd_kernels.h"

#include <atomic>

namespace soccer_vision {
namespace detail {
namespace {

std::atomic<bool> allowed_kernels{true};

bool cpuHasAvx512() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512vbmi");
#else
  return false;
#endif
}

}  // namespace

bool useAvx512Kernels() {
  static const bool cpu = cpuHasAvx512();
  return cpu && allowed_kernels.load(std::memory_order_relaxed);
}

void allowSimdKernels(bool allowed) { allowed_kernels.store(allowed, std::memory_order_relaxed); }

}  // namespace detail
}  // namespace soccer_vision
