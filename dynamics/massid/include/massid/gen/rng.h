#pragma once
/// @file rng.h
/// @brief Portable deterministic random numbers for the generator: std::mt19937_64 (its output
/// sequence is fixed by the standard) with our own uniform and Box-Muller normal, because the
/// standard distributions may differ between library implementations.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>

namespace vid::massid::gen {

/// @brief SplitMix64 step: mixes a seed into a well-spread 64-bit value.
inline std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// @brief Seeded generator of uniform and Gaussian numbers, identical on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(mix_seed(seed)) {}
  /// @brief Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// @brief Uniform in [a, b).
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// @brief Standard normal (Box-Muller, one value per call).
  double normal() {
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  /// @brief Three independent normals (x, y, z drawn in that order) times @p sigma.
  Eigen::Vector3d normal3(double sigma) {
    const double x = normal(), y = normal(), z = normal();
    return Eigen::Vector3d(x, y, z) * sigma;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace vid::massid::gen
