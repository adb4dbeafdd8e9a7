#pragma once
// Dispatch tables for Highway kernels chosen by hydrolux::simd (include/hydrolux/core/simd.hpp)
// instead of Highway's shared library. Use in a foreach_target source, inside `#if HWY_ONCE`:
//   HYDROLUX_SIMD_EXPORT(Kernel);                  // at the namespace of Kernel's HWY_NAMESPACE
//   HYDROLUX_SIMD_DISPATCH(Kernel)(args...);        // calls the chosen target's Kernel
// The tables hold the same entries as HWY_EXPORT's, except the first: Highway's calls into
// libhwy.so to choose, this one is the static (baseline) target and is never selected.
#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

#include "hydrolux/core/simd.hpp"

namespace hydrolux::simd::detail {

// The table index of the chosen target among those compiled into the calling translation unit
// (tu_mask: its HWY_CHOSEN_TARGET_MASK_TARGETS, which depends on the targets it was compiled for).
inline std::size_t table_index(std::int64_t tu_mask) {
  const std::int64_t chosen =
      HWY_CHOSEN_TARGET_SHIFT(enabled_targets()) | HWY_CHOSEN_TARGET_MASK_SCALAR;
  return hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<std::uint64_t>(chosen & tu_mask));
}

}  // namespace hydrolux::simd::detail

#if HWY_IDE || ((HWY_TARGETS & (HWY_TARGETS - 1)) == 0)
// One target compiled (e.g. -march=native builds): no choice to make.
#define HYDROLUX_SIMD_EXPORT(FUNC)                                        \
  HWY_MAYBE_UNUSED static decltype(&HWY_STATIC_DISPATCH(FUNC)) const \
      HWY_CONCAT(FUNC, HydroluxTable)[1] = {&HWY_STATIC_DISPATCH(FUNC)}
#define HYDROLUX_SIMD_DISPATCH(FUNC) HWY_STATIC_DISPATCH(FUNC)
#else
#define HYDROLUX_SIMD_EXPORT(FUNC)                                                            \
  static decltype(&HWY_STATIC_DISPATCH(FUNC)) const HWY_CONCAT(                               \
      FUNC, HydroluxTable)[HWY_MAX_DYNAMIC_TARGETS + 2] = {&HWY_STATIC_DISPATCH(FUNC),        \
                                                           HWY_CHOOSE_TARGET_LIST(FUNC),      \
                                                           HWY_CHOOSE_FALLBACK(FUNC)}
#define HYDROLUX_SIMD_DISPATCH(FUNC) \
  (*(HWY_CONCAT(FUNC, HydroluxTable)[::hydrolux::simd::detail::table_index(HWY_CHOSEN_TARGET_MASK_TARGETS)]))
#endif
