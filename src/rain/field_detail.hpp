#pragma once
// Pieces shared by the rain field and its renderer (not installed).
#include <cmath>
#include <cstdint>

#include "hydrolux/core/vec.hpp"

namespace hydrolux::rain::detail {

// SplitMix64's finaliser: a bijection of 64-bit words that scatters every input bit.
constexpr std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
// The key of item `index` under `seed`: counter-based, so any item is drawn without the others.
constexpr std::uint64_t hash(std::uint64_t seed, std::uint64_t index) { return mix(mix(seed) ^ mix(index + 0x632be59bd9b4e019ULL)); }
// The same with mix(seed) given (a loop over one seed's items mixes it once).
constexpr std::uint64_t hash_mixed(std::uint64_t mixed_seed, std::uint64_t index) {
  return mix(mixed_seed ^ mix(index + 0x632be59bd9b4e019ULL));
}
// A double in [0, 1) from the top 53 bits.
constexpr double unit(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

// p wrapped into the periodic box [lo, lo + size) (the renderer's hot loop and RainField::position).
// A drop's k-th uniform variate from its key (0, 1, 2: its start's x, y, z in the box; 3: its radius;
// 4: its oscillation's phase).
constexpr double variate(std::uint64_t key, int k) { return k == 0 ? unit(key) : unit(mix(key + std::uint64_t(k))); }

// One coordinate wrapped into [lo, lo + size).
inline double wrap1(double p, double lo, double size) {
  const double q = p - lo;
  return lo + q - size * std::floor(q / size);
}
// The same with 1 / size given (the renderer's loop over drops): the product's floor is the
// quotient's, floor(q / size), except within 1e-9 of a whole number, where the division decides (both
// are within a few units in the last place of the true quotient, a few units at most, so away from
// whole numbers they floor alike): the same result without a division for nearly every drop.
inline double wrap1(double p, double lo, double size, double inv_size) {
  const double q = p - lo;
  const double t = q * inv_size;
  double k = std::floor(t);
  if (t - k < 1e-9 || t - k > 1 - 1e-9) k = std::floor(q / size);
  return lo + q - size * k;
}
inline Vec3 wrap(const Vec3& p, const Vec3& lo, const Vec3& size) {
  Vec3 q(0);
  for (int k = 0; k < 3; ++k) q[k] = wrap1(p[k], lo[k], size[k]);
  return q;
}

// The largest alpha a streak of drop radius r, footprint R and length L (pixels) puts on a pixel.
double peak_alpha(double r, double R, double L);

}  // namespace hydrolux::rain::detail
