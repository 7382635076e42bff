#include "pgo/robust.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace keel::pgo {

double dcs_scale(double chi2, double phi) { return std::min(1.0, 2.0 * phi / (phi + chi2)); }

double tls_surrogate(double chi2, double mu, double threshold) {
  if (chi2 <= mu / (mu + 1.0) * threshold) return chi2;
  if (chi2 >= (mu + 1.0) / mu * threshold) return threshold;
  return 2.0 * std::sqrt(threshold * mu * (mu + 1.0) * chi2) - mu * (threshold + chi2);
}

double tls_gnc_weight(double chi2, double mu, double threshold) {
  if (chi2 <= mu / (mu + 1.0) * threshold) return 1.0;
  if (chi2 >= (mu + 1.0) / mu * threshold) return 0.0;
  // Between the two ends χ² > 0, and the expression runs from 1 down to 0; clamp the rounding at the ends.
  return std::clamp(std::sqrt(threshold * mu * (mu + 1.0) / chi2) - mu, 0.0, 1.0);
}

double tls_gnc_initial_mu(double max_chi2, double threshold) {
  if (!(max_chi2 > threshold)) return std::numeric_limits<double>::infinity();
  return threshold / (2.0 * max_chi2 - threshold);
}

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
      if (const double ratio = s / b; std::isfinite(ratio)) {
        const double inv = 1.0 / (1.0 + ratio);
        r = {b * std::log1p(ratio), inv, -inv * inv / b};
      } else {
        // s/b beyond the largest double (a tiny a, a far outlier): log1p(s/b) = log s − log b to within
        // b/s, and ρ' = b/(b + s), ρ'' = −b/(b + s)², without forming s/b.
        const double inv = b / (b + s);
        r = {b * (std::log(s) - std::log(b)), inv, -inv / (b + s)};
      }
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
