#pragma once
/// @file random.h
/// @brief Small, portable, seedable random generators for the renderer and feature simulator.
/// The standard distributions are implementation-defined, so these are written out to keep
/// "same seed -> identical output" across standard libraries.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace vid::sim {

/// @brief SplitMix64 step; also used to derive independent seeds from (seed, stream).
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// @brief Mix a seed with a stream index into a new, decorrelated seed.
inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t s = seed ^ (0xD1B54A32D192ED03ULL * (stream + 1));
  splitmix64(s);
  return splitmix64(s);
}

/// @brief xoshiro256** generator with uniform and normal helpers.
class Rng {
 public:
  /// @brief Seed the 256-bit state from one 64-bit seed through SplitMix64.
  explicit Rng(std::uint64_t seed = 1) {
    std::uint64_t s = seed;
    for (auto& w : s_) w = splitmix64(s);
  }
  /// @brief Next 64 random bits.
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// @brief Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// @brief Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// @brief Uniform integer in [0, n) (n > 0).
  int uniform_int(int n) { return static_cast<int>(uniform() * n); }
  /// @brief Standard normal sample (Box-Muller, second value cached).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 1e-300) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace vid::sim
