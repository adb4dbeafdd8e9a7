#pragma once
// Seeded random numbers. The same seed gives the same sequence on every platform and compiler:
// std::mt19937_64 is fully specified, and the conversion to [0, 1) is done here rather than by
// std::uniform_real_distribution, whose algorithm is implementation-defined.
#include <cstdint>
#include <random>

namespace hydrolux {

// The largest seed every door accepts (CLI --seed, Python seed=, the batch jobs): 2^53, so that a
// seed survives a round trip through JSON and double-precision numbers exactly.
inline constexpr std::uint64_t kMaxSeed = std::uint64_t(1) << 53;

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
