#pragma once
// A random generator whose sequence is the same on every machine: benchmark inputs (sampled
// and scanned meshes) must not depend on the standard library's distributions.

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace clustersurf::detail {

/// Uniform doubles in [0, 1) and standard normals from the raw bits of a 64-bit Mersenne
/// twister (whose output sequence the C++ standard fixes), so samples are portable.
class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u = 1.0 - uniform();  // (0, 1]: log stays finite
    const double v = uniform();
    const double r = std::sqrt(-2.0 * std::log(u));
    spare_ = r * std::sin(2 * std::numbers::pi * v);
    has_spare_ = true;
    return r * std::cos(2 * std::numbers::pi * v);
  }
  Eigen::Vector3d unit_vector() {
    Eigen::Vector3d d;
    do d = Eigen::Vector3d(normal(), normal(), normal());
    while (d.squaredNorm() < 1e-12);
    return d.normalized();
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace clustersurf::detail
