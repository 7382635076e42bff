#include "pgo/robust.hpp"

#include <algorithm>
#include <cmath>

namespace keel::pgo {

double dcs_scale(double chi2, double phi) { return std::min(1.0, 2.0 * phi / (phi + chi2)); }

Rho robust_rho(RobustKernel kernel, double a, double s) {
  Rho r;
  switch (kernel) {
    case RobustKernel::none:
      r = {s, 1.0, 0.0};
      break;
    case RobustKernel::huber: {
      const double b = a * a;
      if (s <= b) {
        r = {s, 1.0, 0.0};
      } else {
        const double root = std::sqrt(s);
        r = {2.0 * a * root - b, a / root, -0.5 * a / (root * s)};
      }
      break;
    }
    case RobustKernel::cauchy: {
      const double b = a * a;
      const double sum = 1.0 + s / b;
      const double inv = 1.0 / sum;
      r = {b * std::log1p(s / b), inv, -inv * inv / b};
      break;
    }
    case RobustKernel::dcs: {
      const double phi = a;
      if (s <= phi) {
        r = {s, 1.0, 0.0};
      } else {
        const double d = phi + s;
        const double q = 2.0 * phi / d;                                  // the DCS scale s (< 1 here)
        r = {3.0 * phi - 4.0 * phi * phi / d, q * q, -2.0 * q * q / d};  // ρ'' = −8φ²/d³ = −2 (2φ/d)² / d
      }
      break;
    }
  }
  return r;
}

}  // namespace keel::pgo
