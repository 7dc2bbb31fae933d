#pragma once
// Counter-based random numbers for the simulated effects: a draw depends only on (seed, stream,
// index), so frame k's noise or delay is the same whichever thread computes it and in whatever
// order -- the offline render_frame() and the running device agree, and tests can replay it.

#include <cmath>
#include <cstdint>

namespace hd::sim {

/// SplitMix64's finaliser: a good 64-bit mix of its input.
inline uint64_t mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t random_bits(uint64_t seed, uint64_t stream, uint64_t index) {
  return mix64(mix64(seed ^ mix64(stream)) + index);
}

/// Uniform in (0, 1).
inline double random_uniform(uint64_t seed, uint64_t stream, uint64_t index) {
  return (static_cast<double>(random_bits(seed, stream, index) >> 11) + 0.5) * 0x1.0p-53;
}

/// Standard normal (Box-Muller on two counter-based uniforms).
inline double random_normal(uint64_t seed, uint64_t stream, uint64_t index) {
  const double u1 = random_uniform(seed, stream, 2 * index);
  const double u2 = random_uniform(seed, stream, 2 * index + 1);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace hd::sim
