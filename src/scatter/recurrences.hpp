#pragma once
// Types shared by the per-target recurrences (src/scatter/recurrences-inl.h, read once per SIMD
// target) and their callers, defined once here.

namespace hydrolux::scatter::detail {

// An order where the unnormalised psi_n(z) of the recurrences was rescaled:
// D_n = 2^shift p[n] / p[n+1] - n/z there (recurrences-inl.h).
struct Rescale {
  int n, shift;
};

// Orders the downward recurrence may run above its top order (its approximate start far above
// the turning point): its scratch array needs this many more values.
inline constexpr int kMaxMillerOrders = 30;

}  // namespace hydrolux::scatter::detail
