// keel::lie — numerically stable scalar coefficient functions shared by the
// SO(2)/SO(3)/SE(2)/SE(3) exponential maps and Jacobians.
//
// Each function of the rotation angle theta >= 0 is an entire (or, for
// jl_inverse_coeff, analytic on |theta| < 2 pi) function.  The closed forms suffer
// catastrophic cancellation near theta = 0, so below a threshold we evaluate the
// Taylor series instead (enough terms that the truncation error is far below
// machine precision at the threshold).
#pragma once

#include <cmath>

namespace keel::lie::detail {

/// Threshold below which the Taylor series are used.
inline constexpr double kSeriesThreshold = 1.0;

/// sum_{k=0}^{n-1} (-1)^k theta^{2k} / (2k + offset)!
inline double alternating_inverse_factorial_series(double theta2, int offset, int n_terms = 12) {
  double fact = 1.0;
  for (int i = 2; i <= offset; ++i) fact *= static_cast<double>(i);
  double term = 1.0 / fact;
  double sum = 0.0;
  for (int k = 0; k < n_terms; ++k) {
    sum += term;
    const double a = static_cast<double>(2 * k + offset + 1);
    term *= -theta2 / (a * (a + 1.0));
  }
  return sum;
}

/// sin(theta) / theta
inline double sinc(double theta) {
  if (theta < kSeriesThreshold) return alternating_inverse_factorial_series(theta * theta, 1);
  return std::sin(theta) / theta;
}

/// (1 - cos(theta)) / theta^2
inline double one_minus_cos_over_theta2(double theta) {
  if (theta < kSeriesThreshold) return alternating_inverse_factorial_series(theta * theta, 2);
  const double s = std::sin(0.5 * theta);
  return 2.0 * s * s / (theta * theta);
}

/// (theta - sin(theta)) / theta^3
inline double theta_minus_sin_over_theta3(double theta) {
  if (theta < kSeriesThreshold) return alternating_inverse_factorial_series(theta * theta, 3);
  return (theta - std::sin(theta)) / (theta * theta * theta);
}

/// (theta^2 + 2 cos(theta) - 2) / (2 theta^4)   (Barfoot's Q, second coefficient)
inline double q_coeff2(double theta) {
  if (theta < kSeriesThreshold) return alternating_inverse_factorial_series(theta * theta, 4);
  const double t2 = theta * theta;
  return (t2 + 2.0 * std::cos(theta) - 2.0) / (2.0 * t2 * t2);
}

/// (2 theta - 3 sin(theta) + theta cos(theta)) / (2 theta^5)   (Barfoot's Q, third coefficient)
/// Series: sum_{m>=0} (-1)^m (m+1) theta^{2m} / (2m+5)!
inline double q_coeff3(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesThreshold) {
    double fact = 120.0;  // 5!
    double sum = 0.0;
    double power = 1.0;
    for (int m = 0; m < 12; ++m) {
      const double sign = (m % 2 == 0) ? 1.0 : -1.0;
      sum += sign * static_cast<double>(m + 1) * power / fact;
      power *= t2;
      fact *= static_cast<double>((2 * m + 6) * (2 * m + 7));
    }
    return sum;
  }
  return (2.0 * theta - 3.0 * std::sin(theta) + theta * std::cos(theta)) / (2.0 * t2 * t2 * theta);
}

/// (1 - (theta/2) cot(theta/2)) / theta^2 = 1/theta^2 - (1 + cos theta) / (2 theta sin theta).
/// Coefficient of phi^ phi^ in the inverse left Jacobian of SO(3).  Series (Bernoulli numbers):
/// 1/12 + theta^2/720 + theta^4/30240 + theta^6/1209600 + theta^8/47900160 + ...
/// Singular at theta = 2 pi (outside the principal domain of log).
inline double jl_inverse_coeff(double theta) {
  if (theta < 0.1) {
    const double t2 = theta * theta;
    return 1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0 + t2 * (1.0 / 1209600.0 + t2 / 47900160.0)));
  }
  const double h = 0.5 * theta;
  return (1.0 - h * std::cos(h) / std::sin(h)) / (theta * theta);
}

/// (theta/2) cot(theta/2) = 1 - theta^2 * jl_inverse_coeff(theta).
inline double half_theta_cot_half_theta(double theta) {
  return 1.0 - theta * theta * jl_inverse_coeff(theta);
}

}  // namespace keel::lie::detail
