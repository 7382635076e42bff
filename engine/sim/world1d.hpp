// The simulated 1D world of thesis §2.7.1: one state x observed directly by m measurements, some of them
// outliers.
//
//   inliers          z ~ N(x, σ_in²), σ_in fixed;
//   aliased group    one perceptually aliased group: every member drawn from the same Gaussian N(μ_a, σ_a²),
//   whose
//                    mean and standard deviation are themselves random per world (fixed within the world), so
//                    the group is internally consistent but (usually) not with the inliers;
//   random outliers  each from its own Gaussian N(μ_j, σ_j²) with random mean and standard deviation.
//
// The variances are known and used in the Mahalanobis distance of a pair (dof = kWorld1DDof = 1):
//
//   q_uv = (z_u − z_v)² / (σ_u² + σ_v²)                                            (the 1D case of eq. 2.4)
//
// The combinatorial "gold standard" of eq. 2.5 is pcm/combinatorial.hpp; the Monte-Carlo study of
// Figs. 2.2–2.3 is study/ch2/world1d.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/random.hpp"
#include "pcm/consistency.hpp"

namespace keel::sim {

// Degrees of freedom of a loop error in the 1D world (a scalar): the dof of its consistency threshold,
// pcm::consistency_threshold(p, kWorld1DDof).
inline constexpr int kWorld1DDof = 1;

enum class MeasurementLabel { inlier, aliased, random };
std::string_view to_string(MeasurementLabel label);  // "inlier" | "aliased" | "random"
MeasurementLabel measurement_label_from_string(std::string_view s);

struct World1DOptions {
  double x = 0.0;             // the true state
  double sigma_inlier = 1.0;  // standard deviation of every inlier, > 0
  int inliers_min = 4;        // number of inliers, uniform in [min, max]; 0 <= min <= max
  int inliers_max = 10;
  int aliased_min = 2;  // size of the perceptually aliased group, uniform in [min, max]
  int aliased_max = 6;
  int random_min = 2;  // number of random outliers, uniform in [min, max]
  int random_max = 6;
  double outlier_mean_range = 10.0;  // μ_a and each μ_j uniform in [x − R, x + R]; R >= 0
  double outlier_sigma_min = 0.5;    // σ_a and each σ_j uniform in [min, max]; 0 < min <= max
  double outlier_sigma_max = 3.0;
  bool shuffle = true;  // randomly permute the measurements (otherwise: inliers, aliased, random)
  // Throws std::invalid_argument naming the violated constraint (also when max counts sum to 0).
  void validate() const;
};

// A World1DOptions with exactly `total` measurements: round(inlier_fraction·total) inliers,
// round(aliased_fraction·total) aliased, the rest random (used for sweeps over the number of measurements,
// Fig. 2.3). Fractions in [0, 1] with sum <= 1, total >= 1; throws std::invalid_argument otherwise.
World1DOptions world1d_options_with_total(const World1DOptions& base, int total, double inlier_fraction,
                                          double aliased_fraction);

struct World1D {
  double x = 0.0;
  std::vector<double> z;                           // measurements
  std::vector<double> sigma;                       // their known standard deviations
  std::vector<MeasurementLabel> labels;            // ground truth
  double aliased_mean = 0.0, aliased_sigma = 0.0;  // the aliased group's Gaussian
  int size() const { return static_cast<int>(z.size()); }
  int count(MeasurementLabel label) const;
};

// Draws one world from `rng` (counts, then inliers, the aliased group, the random outliers, then the
// shuffle).
World1D generate_world1d(const World1DOptions& options, core::Rng& rng);
// World `world_index` of experiment `seed`: drawn from keel::core::Rng::stream(seed, world_index), so every
// world is independent of how many others are generated and in which order (results do not depend on the
// thread count).
World1D generate_world1d(const World1DOptions& options, std::uint64_t seed, std::uint64_t world_index);

// Q of the world: q_uv = (z_u − z_v)² / (σ_u² + σ_v²), zero diagonal, dof = 1. Throws std::invalid_argument
// for an empty world, mismatched sizes or non-positive / non-finite σ or non-finite z.
pcm::ConsistencyMatrix world1d_consistency_matrix(const World1D& world);

}  // namespace keel::sim
