// keel::pgo — robust kernels on the squared whitened residual χ² = rᵀΩr of one measurement.
//
// Convention (the same as Ceres' LossFunction): the cost of a measurement is ½ ρ(χ²), so its gradient is
// ρ'(χ²) · Jᵀ Ω r and ρ'(χ²) is the weight iteratively reweighted least squares would give it. A kernel is
// "quadratic" (ρ(χ²) = χ²) where it trusts the measurement.
//
// Dynamic Covariance Scaling (Agarwal, Tipaldi, Spinello, Stachniss, Burgard, ICRA 2013; thesis §2.7 uses φ =
// 5). DCS scales the whitened residual of an edge by
//     s = min(1, 2φ / (φ + χ²)),
// i.e. its information by s². Read as an M-estimator, that is the kernel whose IRLS weight is s²:
//     ρ'(χ²) = s² = 1                      for χ² ≤ φ,
//                 = 4φ² / (φ + χ²)²         for χ² > φ.
// Integrating with ρ(0) = 0 and requiring continuity at χ² = φ:
//     χ² ≤ φ:  ρ = χ²;
//     χ² > φ:  ρ = C − 4φ²/(φ + χ²), and C − 4φ²/(2φ) = φ gives C = 3φ, so
//              ρ = 3φ − 4φ²/(φ + χ²) = φ (3χ² − φ) / (φ + χ²),
//     ρ'' = 0 for χ² < φ and −8φ² / (φ + χ²)³ for χ² > φ.
// ρ, ρ' are continuous at φ (ρ' = 1 on both sides); ρ'' jumps from 0 to −1/φ there. ρ is bounded by 3φ, so a
// gross outlier contributes at most 3φ/2 to the cost and its weight s² → 0 (redescending, like Geman–McClure,
// of which DCS is closely related, as Agarwal et al. discuss). DCS as published freezes s at each
// linearization point and minimizes Σ s² χ² — iteratively reweighted least squares with weight s². A fixed
// point of that iteration has Σ s² ∇χ² = 0, which is exactly a stationary point of ½ Σ ρ(χ²) with ρ' = s²: so
// minimizing this ρ with Ceres finds the DCS solutions. Ceres applies its curvature (Triggs) correction only
// where ρ'' > 0; DCS has ρ'' ≤ 0 everywhere, so each Ceres step scales the edge's whitened residual and
// Jacobian by √ρ' = s — the DCS step itself — while step acceptance uses the cost ½ Σ ρ(χ²).
#pragma once

#include "pgo/options.hpp"

namespace keel::pgo {

// ρ(χ²) and its first two derivatives with respect to χ².
struct Rho {
  double rho = 0.0;  // ρ(χ²)
  double d1 = 1.0;   // ρ'(χ²), the IRLS weight
  double d2 = 0.0;   // ρ''(χ²)
};

// The kernel at χ² ≥ 0 with `parameter` (DCS φ, Huber/Cauchy a; ignored by none):
//   none:   ρ = χ²
//   huber:  ρ = χ² for χ² ≤ a², 2a√χ² − a² beyond (ρ' = a/√χ²)
//   cauchy: ρ = a² log(1 + χ²/a²) (ρ' = 1/(1 + χ²/a²))
//   dcs:    as derived above with φ = parameter
[[nodiscard]] Rho robust_rho(RobustKernel kernel, double parameter, double chi2);

// The DCS scaling s = min(1, 2φ/(φ + χ²)) of Agarwal et al. (2013).
[[nodiscard]] double dcs_scale(double chi2, double phi);

// Graduated non-convexity for truncated least squares (Yang, Antonante, Tzoumas, Carlone, "Graduated
// Non-Convexity for Robust Spatial Perception", RA-L 2020, §III-B; GTSAM's GncOptimizer). TLS gives a
// measurement the cost min(χ², c̄²), c̄² the inlier threshold. Its surrogate with control parameter μ > 0 is
//     ρ_μ(χ²) = χ²                                  for χ² ≤ μ/(μ+1) · c̄²,
//             = 2 c̄ √(μ(μ+1)) √χ² − μ (c̄² + χ²)     between,
//             = c̄²                                  for χ² ≥ (μ+1)/μ · c̄²,
// convex for μ → 0 and TLS itself as μ → ∞. GNC starts at μ₀ = c̄² / (2 max χ² − c̄²) (where every residual is
// in the convex part), alternates a weighted least-squares solve with the weights below and μ ← factor·μ.
// The weight of a measurement is w = dρ_μ/dχ²:
//     w = 1 for χ² ≤ μ/(μ+1) c̄²,  0 for χ² ≥ (μ+1)/μ c̄²,  c̄ √(μ(μ+1)/χ²) − μ between (in [0, 1]).
[[nodiscard]] double tls_surrogate(double chi2, double mu, double threshold);  // ρ_μ(χ²); threshold = c̄²
[[nodiscard]] double tls_gnc_weight(double chi2, double mu, double threshold);
// μ₀ for the largest χ² of the measurements; +∞ when max χ² ≤ c̄² (every measurement an inlier: nothing to
// graduate).
[[nodiscard]] double tls_gnc_initial_mu(double max_chi2, double threshold);

}  // namespace keel::pgo
