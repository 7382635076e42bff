// Fig. 2.2 and Fig. 2.3 (§2.7.1) on the simulated 1D world (sim/world1d.hpp): the Monte-Carlo study that
// runs every selector on the same worlds, against the combinatorial gold standard of eq. 2.5
// (pcm/combinatorial.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pcm/combinatorial.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "repro/run.hpp"
#include "sim/world1d.hpp"

namespace keel::study::ch2 {

using pcm::CombinatorialMethod;
using pcm::kCombinatorialExhaustiveMax;
using pcm::kCombinatorialPrunedMax;

// ---------------------------------------------------------------------------------------------------------------
// Monte-Carlo study over 1D worlds (Figs. 2.2 and 2.3): every world is generated from its own random stream,
// its Q is built once (not timed), and each selector runs on the same Q.

enum class Selector1D { combinatorial, pcm_exact, pcm_heuristic, scgp, ransac };
std::string_view to_string(
    Selector1D s);  // "combinatorial" | "pcm_exact" | "pcm_heuristic" | "scgp" | "ransac"
Selector1D selector1d_from_string(std::string_view s);

struct World1DStudyOptions {
  sim::World1DOptions world;
  double pcm_gamma = 0.0;  // γ of PCM and of the combinatorial solution (eq. 2.5); also the γ against which
                           // inconsistent pairs are counted for every method (Fig. 2.2); > 0
  double ransac_gamma = 0.0;  // RANSAC's own likelihood threshold on q_uv; > 0
  pcm::ScgpOptions scgp;
  CombinatorialMethod combinatorial = CombinatorialMethod::pruned;
  std::vector<Selector1D> selectors = {Selector1D::combinatorial, Selector1D::pcm_exact,
                                       Selector1D::pcm_heuristic, Selector1D::scgp, Selector1D::ransac};
  std::size_t worlds = 1000;  // >= 1
  void validate() const;      // throws std::invalid_argument naming the field
};

// One selector on one world.
struct World1DOutcome {
  int size = 0;                // number of selected measurements
  int inconsistent_pairs = 0;  // pairs of the selection with q > pcm_gamma (count_inconsistent_pairs)
  int inliers = 0;             // selected measurements labelled inlier
  double time_s = 0.0;         // wall time of the selection (Selection::time_s / CombinatorialResult::time_s)
};

struct World1DStudy {
  std::vector<Selector1D> selectors;                          // as requested
  std::vector<int> measurements;                              // m of each world
  std::vector<int> inliers;                                   // inliers in each world
  std::vector<std::vector<World1DOutcome>> outcome;           // [selector][world]
  const std::vector<World1DOutcome>& of(Selector1D s) const;  // throws std::invalid_argument if not run
};

// Runs the study in one sharded trial loop on the context's threads: world i is
// sim::generate_world1d(options.world, streams.seed(), streams.index(i)). Progress advances once per world
// (may be null).
[[nodiscard]] World1DStudy run_world1d_study(const World1DStudyOptions& options,
                                             const repro::RunContext& context,
                                             core::Progress* progress = nullptr);

// How selectors compare with the combinatorial maximum over a study's worlds (Fig. 2.2): histograms over
// ranges shared by all the selectors compared.
struct SelectorComparison {
  Selector1D selector = Selector1D::pcm_exact;
  double match_rate = 0.0, larger_rate = 0.0,
         smaller_rate = 0.0;                              // fractions of worlds where the selection's size
                                                          // equals / exceeds / falls short of the maximum
  long long inconsistent_total = 0;                       // pairs violating eq. 2.3, summed over the worlds
  double inconsistent_mean = 0.0;                         // per world
  double inconsistent_rate = 0.0;                         // fraction of worlds with at least one
  double time_mean_s = 0.0;                               // mean selection wall time
  std::vector<double> size_diff_hist, inconsistent_hist;  // fractions of worlds per bin
};
struct CombinatorialComparison {
  std::vector<double> size_diff_bins;     // size returned − maximum size, one bin per integer
  std::vector<double> inconsistent_bins;  // 0 … the largest count of inconsistent pairs
  std::vector<SelectorComparison> rows;   // one per selector compared, in the order given
  int heuristic_above_exact = 0;  // worlds where PCM-Heuristic returned more than PCM-Exact (when both ran)
};
// Needs the combinatorial selector in the study; throws std::invalid_argument naming a selector that was not
// run.
[[nodiscard]] CombinatorialComparison compare_to_combinatorial(const World1DStudy& study,
                                                               const std::vector<Selector1D>& selectors);

// Fig. 2.3: selection time against the number of measurements m. For each m, worlds of exactly m measurements
// (sim::world1d_options_with_total with the given fractions) drawn from the context's streams k << 32 | i,
// the same for every curve; PCM-Exact, PCM-Heuristic, SCGP, RANSAC and the exhaustive enumeration (m <=
// exhaustive_max) in one pass, the pruned subset search (m <= pruned_max) in a second pass over the same
// worlds.
struct TimingSweepOptions {
  World1DStudyOptions base;  // noise model, thresholds, SCGP, worlds per size (counts are replaced)
  std::vector<int> sizes;    // m, increasing, >= 1
  double inlier_fraction = 0.5, aliased_fraction = 0.25;
  int exhaustive_max = kCombinatorialExhaustiveMax;  // in [1, kCombinatorialExhaustiveMax]
  int pruned_max = kCombinatorialPrunedMax;          // in [1, kCombinatorialPrunedMax]
  void validate() const;                             // throws std::invalid_argument naming the field
  [[nodiscard]] std::size_t work() const;            // worlds × passes: the progress total
};
struct TimingCurve {
  std::string name;  // combinatorial_exhaustive, combinatorial_pruned, pcm_exact, pcm_heuristic, scgp, ransac
  std::vector<double> m;              // the sizes this curve ran at
  std::vector<double> median_time_s;  // median wall time of one selection at each m (robust to preemption)
  std::vector<double> size_mean;      // mean selected size at each m
};
struct TimingSweep {
  std::vector<TimingCurve> curves;       // in the order listed above
  std::vector<double> heuristic_match;   // per m: fraction of worlds where PCM-Heuristic's size = PCM-Exact's
  long long combinatorial_checked = 0;   // combinatorial runs (both variants) compared with PCM-Exact's size
  long long combinatorial_mismatch = 0;  // … of which with a different size
};
[[nodiscard]] TimingSweep run_timing_sweep(const TimingSweepOptions& options,
                                           const repro::RunContext& context,
                                           core::Progress* progress = nullptr);

}  // namespace keel::study::ch2
