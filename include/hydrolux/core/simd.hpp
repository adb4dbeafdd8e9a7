#pragma once
// Which SIMD instruction set hydrolux's Google Highway kernels run on, chosen once per process.
//
// hydrolux compiles its kernels for several targets with Highway (foreach_target: AVX-512, AVX2,
// SSE4, SSSE3 and an emulated 128-bit fallback on x86-64; NEON on Arm) and picks one at run time.
// It does the picking itself instead of through Highway's shared library: loading libhwy.so runs
// a timer calibration in a static initialiser that cost 3.5 ms of every process start (measured
// with perf on the 2-core EPYC CI machine), more than `hydrolux mie` spends on a small sphere.
// Highway's headers are used as they are; only its two run-time functions (which CPU features
// exist, and the global choice) are replaced, so no hydrolux binary loads libhwy.so.
//
// Targets are Highway's bits (HWY_AVX3, HWY_AVX2, ... in hwy/detect_targets.h).
#include <cstdint>

namespace hydrolux::simd {

// The Highway targets this CPU and operating system can run. x86-64: from CPUID and XGETBV with
// the feature groups Highway 1.0 requires for each target (SSSE3; SSE4 = SSE4.1, SSE4.2, CLMUL,
// AES; AVX2 = AVX, AVX2, BMI1, BMI2, FMA, F16C, LZCNT and the OS saving YMM state; AVX3 = AVX-512
// F, VL, DQ, BW and the OS saving ZMM and opmask state). Other architectures: the compile-time
// baseline only (NEON on aarch64). The emulated and scalar fallbacks are always included.
std::int64_t supported_targets();

// The targets dispatch may choose from: supported_targets(), or what set_targets_for_test gave.
std::int64_t enabled_targets();

// Restricts dispatch to `targets` (one bit: exactly that target) for tests that run every
// compiled target; 0 restores supported_targets(). Not thread-safe with concurrent kernels.
void set_targets_for_test(std::int64_t targets);

// The name of the best target in `targets` (e.g. "AVX3", "AVX2", "EMU128").
const char* target_name(std::int64_t target);

}  // namespace hydrolux::simd
