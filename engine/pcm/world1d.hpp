// The simulated 1D world of thesis §2.7.1: one state x observed directly by m measurements, some of them outliers.
//
//   inliers          z ~ N(x, σ_in²), σ_in fixed;
//   aliased group    one perceptually aliased group: every member drawn from the same Gaussian N(μ_a, σ_a²), whose
//                    mean and standard deviation are themselves random per world (fixed within the world), so the
//                    group is internally consistent but (usually) not with the inliers;
//   random outliers  each from its own Gaussian N(μ_j, σ_j²) with random mean and standard deviation.
//
// The variances are known and used in the Mahalanobis distance of a pair (dof = 1):
//
//   q_uv = (z_u − z_v)² / (σ_u² + σ_v²)                                            (the 1D case of eq. 2.4)
//
// Also here: the combinatorial "gold standard" of eq. 2.5 — a search over the subsets S ∈ {0,1}^m that does not use
// the clique code — and the count of inconsistent pairs of a returned set (Fig. 2.2's second row).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"

namespace keel::core {
class Progress;
}

namespace keel::pcm {

enum class MeasurementLabel { inlier, aliased, random };
std::string to_string(MeasurementLabel label);  // "inlier" | "aliased" | "random"

struct World1DOptions {
  double x = 0.0;              // the true state
  double sigma_inlier = 1.0;   // standard deviation of every inlier, > 0
  int inliers_min = 4;         // number of inliers, uniform in [min, max]; 0 <= min <= max
  int inliers_max = 10;
  int aliased_min = 2;         // size of the perceptually aliased group, uniform in [min, max]
  int aliased_max = 6;
  int random_min = 2;          // number of random outliers, uniform in [min, max]
  int random_max = 6;
  double outlier_mean_range = 10.0;  // μ_a and each μ_j uniform in [x − R, x + R]; R >= 0
  double outlier_sigma_min = 0.5;    // σ_a and each σ_j uniform in [min, max]; 0 < min <= max
  double outlier_sigma_max = 3.0;
  bool shuffle = true;  // randomly permute the measurements (otherwise: inliers, aliased, random)
  // Throws std::invalid_argument naming the violated constraint (also when max counts sum to 0).
  void validate() const;
};

// A World1DOptions with exactly `total` measurements: round(inlier_fraction·total) inliers,
// round(aliased_fraction·total) aliased, the rest random (used for sweeps over the number of measurements, Fig. 2.3).
// Fractions in [0, 1] with sum <= 1, total >= 1; throws std::invalid_argument otherwise.
World1DOptions world1d_options_with_total(const World1DOptions& base, int total, double inlier_fraction,
                                          double aliased_fraction);

struct World1D {
  double x = 0.0;
  std::vector<double> z;                 // measurements
  std::vector<double> sigma;             // their known standard deviations
  std::vector<MeasurementLabel> labels;  // ground truth
  double aliased_mean = 0.0, aliased_sigma = 0.0;  // the aliased group's Gaussian
  int size() const { return static_cast<int>(z.size()); }
  int count(MeasurementLabel label) const;
};

// Draws one world from `rng` (counts, then inliers, the aliased group, the random outliers, then the shuffle).
World1D generate_world1d(const World1DOptions& options, core::Rng& rng);
// World `world_index` of experiment `seed`: drawn from keel::core::Rng::stream(seed, world_index), so every world is
// independent of how many others are generated and in which order (results do not depend on the thread count).
World1D generate_world1d(const World1DOptions& options, std::uint64_t seed, std::uint64_t world_index);

// Q of the world: q_uv = (z_u − z_v)² / (σ_u² + σ_v²), zero diagonal, dof = 1. Throws std::invalid_argument for an
// empty world, mismatched sizes or non-positive / non-finite σ or non-finite z.
ConsistencyMatrix world1d_consistency_matrix(const World1D& world);

// Combinatorial solution of eq. 2.5 straight from Q and γ, independent of the clique code: the largest S ⊆ {0..m−1}
// with q_uv <= γ and q_vu <= γ for all u ≠ v in S.
enum class CombinatorialMethod {
  exhaustive,  // all 2^m subsets, each tested for pairwise consistency (m <= kCombinatorialExhaustiveMax)
  pruned,      // depth-first include/exclude over the candidates in index order; a candidate is only included when
               // consistent with every included one, and a branch stops when even taking all remaining candidates
               // could not reach the best size (m <= kCombinatorialPrunedMax)
};
std::string to_string(CombinatorialMethod m);
CombinatorialMethod combinatorial_method_from_string(const std::string& s);  // "exhaustive" | "pruned"
inline constexpr int kCombinatorialExhaustiveMax = 30;
inline constexpr int kCombinatorialPrunedMax = 64;

struct CombinatorialResult {
  std::vector<int> selected;   // one maximum pairwise consistent set, sorted (exhaustive: smallest bitmask)
  long long optimal_sets = 0;  // number of distinct maximum pairwise consistent sets
  long long subsets_visited = 0;  // exhaustive: 2^m; pruned: search nodes
  double time_s = 0.0;
};
// Throws std::invalid_argument for a bad Q or γ (as select_pcm) or m above the method's limit.
CombinatorialResult max_consistent_set_combinatorial(const ConsistencyMatrix& Q, double gamma,
                                                     CombinatorialMethod method = CombinatorialMethod::pruned);

// ---------------------------------------------------------------------------------------------------------------
// Monte-Carlo study over 1D worlds (Figs. 2.2 and 2.3): every world is generated from its own random stream, its Q is
// built once (not timed), and each selector runs on the same Q.

enum class Selector1D { combinatorial, pcm_exact, pcm_heuristic, scgp, ransac };
std::string to_string(Selector1D s);  // "combinatorial" | "pcm_exact" | "pcm_heuristic" | "scgp" | "ransac"
Selector1D selector1d_from_string(const std::string& s);

struct World1DStudyOptions {
  World1DOptions world;
  double pcm_gamma = 0.0;     // γ of PCM and of the combinatorial solution (eq. 2.5); also the γ against which
                              // inconsistent pairs are counted for every method (Fig. 2.2); > 0
  double ransac_gamma = 0.0;  // RANSAC's own likelihood threshold on q_uv; > 0
  ScgpOptions scgp;
  CombinatorialMethod combinatorial = CombinatorialMethod::pruned;
  std::vector<Selector1D> selectors = {Selector1D::combinatorial, Selector1D::pcm_exact, Selector1D::pcm_heuristic,
                                       Selector1D::scgp, Selector1D::ransac};
  std::uint64_t seed = 0;         // experiment seed
  std::uint64_t stream_base = 0;  // world i draws from Rng::stream(seed, stream_base + i)
  std::size_t worlds = 1000;      // >= 1
  unsigned threads = 0;           // 0 = keel::core::default_threads(); results do not depend on it
  void validate() const;          // throws std::invalid_argument naming the field
};

// One selector on one world.
struct World1DOutcome {
  int size = 0;                // number of selected measurements
  int inconsistent_pairs = 0;  // pairs of the selection with q > pcm_gamma (count_inconsistent_pairs)
  int inliers = 0;             // selected measurements labelled inlier
  double time_s = 0.0;         // wall time of the selection (Selection::time_s / CombinatorialResult::time_s)
};

struct World1DStudy {
  std::vector<Selector1D> selectors;                 // as requested
  std::vector<int> measurements;                     // m of each world
  std::vector<int> inliers;                          // inliers in each world
  std::vector<std::vector<World1DOutcome>> outcome;  // [selector][world]
  const std::vector<World1DOutcome>& of(Selector1D s) const;  // throws std::invalid_argument if not run
};

// Runs the study on options.threads threads (parallel_for over worlds; progress advanced once per world, may be null).
World1DStudy run_world1d_study(const World1DStudyOptions& options, core::Progress* progress = nullptr);

// Number of pairs {u, v} of `set` that violate eq. 2.3 (q_uv > γ or q_vu > γ). `set` must hold distinct indices in
// range (std::invalid_argument otherwise).
int count_inconsistent_pairs(const ConsistencyMatrix& Q, const std::vector<int>& set, double gamma);

}  // namespace keel::pcm
