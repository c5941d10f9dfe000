// The run-time choice of the AVX-512 kernels (grid scan, classification of rectangles): the
// build targets plain x86-64, and each kernel has a portable twin with equal results.
#pragma once

namespace soccer_vision {
namespace detail {

// True when the CPU has AVX-512 F, BW, VL and VBMI and the kernels are allowed.
bool useAvx512Kernels();
// false makes every caller take the portable kernels (tests compare the two); true again
// lets the CPU decide.
void allowSimdKernels(bool allowed);

}  // namespace detail
}  // namespace soccer_vision
