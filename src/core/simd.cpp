// Run-time SIMD target choice without libhwy.so (see include/hydrolux/core/simd.hpp).
#include "hydrolux/core/simd.hpp"

#include <hwy/targets.h>

#include <atomic>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace hydrolux::simd {

namespace {

#if defined(__x86_64__) || defined(__i386__)
bool bit(unsigned reg, int b) { return (reg >> b) & 1u; }

std::int64_t detect_x86() {
  std::int64_t targets = 0;
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(0, &a, &b, &c, &d)) return targets;
  const unsigned max_leaf = a;
  unsigned c1 = 0, b7 = 0, c81 = 0;
  if (__get_cpuid(1, &a, &b, &c, &d)) c1 = c;
  if (max_leaf >= 7) {
    __cpuid_count(7, 0, a, b, c, d);
    b7 = b;
  }
  if (__get_cpuid(0x80000001u, &a, &b, &c, &d)) c81 = c;

  const bool ssse3 = bit(c1, 9);
  const bool sse4 = ssse3 && bit(c1, 19) && bit(c1, 20) && bit(c1, 1) && bit(c1, 25);  // 4.1 4.2 CLMUL AES
  if (ssse3) targets |= HWY_SSSE3;
  if (sse4) targets |= HWY_SSE4;

  // The OS must save the YMM (and for AVX-512 the opmask and ZMM) registers: XCR0 via XGETBV,
  // available when OSXSAVE is set.
  unsigned long long xcr0 = 0;
  if (bit(c1, 27)) {
    unsigned lo = 0, hi = 0;
    __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    xcr0 = (static_cast<unsigned long long>(hi) << 32) | lo;
  }
  const bool os_ymm = (xcr0 & 0x6) == 0x6;
  const bool os_zmm = os_ymm && (xcr0 & 0xE0) == 0xE0;
  const bool avx2 = sse4 && os_ymm && bit(c1, 28) /* AVX */ && bit(c1, 12) /* FMA */ &&
                    bit(c1, 29) /* F16C */ && bit(b7, 3) /* BMI1 */ && bit(b7, 5) /* AVX2 */ &&
                    bit(b7, 8) /* BMI2 */ && bit(c81, 5) /* LZCNT */;
  if (avx2) targets |= HWY_AVX2;
  const bool avx3 = avx2 && os_zmm && bit(b7, 16) /* F */ && bit(b7, 17) /* DQ */ &&
                    bit(b7, 30) /* BW */ && bit(b7, 31) /* VL */;
  if (avx3) targets |= HWY_AVX3;
  return targets;
}
#endif

std::int64_t detect() {
  std::int64_t targets = HWY_EMU128 | HWY_SCALAR | HWY_STATIC_TARGET;
#if defined(__x86_64__) || defined(__i386__)
  targets |= detect_x86();
#endif
  return targets;
}

std::atomic<std::int64_t> g_enabled{0};

}  // namespace

std::int64_t supported_targets() {
  static const std::int64_t targets = detect();
  return targets;
}

std::int64_t enabled_targets() {
  const std::int64_t t = g_enabled.load(std::memory_order_relaxed);
  return t != 0 ? t : supported_targets();
}

void set_targets_for_test(std::int64_t targets) {
  g_enabled.store(targets, std::memory_order_relaxed);
}

const char* target_name(std::int64_t target) {
  // The best (lowest) bit names the target, as Highway orders them.
  return hwy::TargetName(target & -target);
}

}  // namespace hydrolux::simd
