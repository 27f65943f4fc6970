#pragma once
// Random material imperfection: per particle, c and phi are scaled by (1 + d), d uniform in
// [-a, a], drawn in particle order from a 64-bit Mersenne Twister seeded from the input.
// std::mt19937_64's sequence is fixed by the C++ standard and the mapping to [0, 1) below is ours
// (std::uniform_real_distribution is not specified bit for bit), so the same seed gives the same
// field with any standard library. Cohesion is drawn before the friction angle for each particle.
#include "tsuchi/model/config.hpp"

#include <cstdint>
#include <random>
#include <vector>

namespace tsuchi {

class ImperfectionField {
 public:
  explicit ImperfectionField(const ImperfectionConfig& c) : c_(c), rng_(c.seed) {}

  // Factors for the next particle.
  void next(double& c_scale, double& phi_scale) {
    c_scale = c_.cohesion ? 1.0 + draw() : 1.0;
    phi_scale = c_.friction ? 1.0 + draw() : 1.0;
  }

 private:
  double draw() {
    const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;  // [0, 1), 53 random bits
    return c_.amplitude * (2.0 * u - 1.0);
  }

  ImperfectionConfig c_;
  std::mt19937_64 rng_;
};

}  // namespace tsuchi
