#pragma once
// Seeded random numbers. The same seed gives the same sequence on every platform and compiler:
// std::mt19937_64 is fully specified, and the conversion to [0, 1) is done here rather than by
// std::uniform_real_distribution, whose algorithm is implementation-defined.
#include <cstdint>
#include <random>

namespace hydrolux {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  // Uniform double in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  std::uint64_t bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace hydrolux
