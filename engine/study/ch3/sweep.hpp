// What the sweep studies (Sensitivity and RegimeGrid) share: the field's σ ranges read from the config, the
// world of a sweep point, and Proposed's paired comparisons against each other method at one point, tallied
// over points. Internal to engine/study/ch3 (not exported).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/grading.hpp"
#include "repro/results.hpp"
#include "sim/alignment_world.hpp"
#include "study/ch3/comparison.hpp"
#include "study/ch3/sensitivity.hpp"

namespace keel::study::ch3 {

// `field_sigma_min` and `field_sigma_max`: the bump σ ranges (m), pairwise.
std::vector<std::pair<double, double>> read_sigma_ranges(const core::ConfigTable& p);

// The world of a point: the base world with the point's noise, query size and σ range, the bump count scaled
// by E[σ²] of the base range over that of the point's (E[σ²] = (a² + ab + b²)/3 for σ ~ U[a, b]).
sim::AlignmentWorldOptions world_of_point(sim::AlignmentWorldOptions w, const Sensitivity::Point& p);

// Proposed against each other method at one point, by the paired rule (median of per-world differences), read
// from the experiment's family after Holm's correction.
struct PairedAtPoint {
  std::vector<repro::PairedComparison> rot, trans;  // [other method]
  std::vector<std::string> others;
};

// The other methods' names and Proposed's index (SIZE_MAX: no Proposed).
std::size_t proposed_index(const AlignmentStudyOutcome& st);

// Adds one point's comparisons to the family under "<prefix>.<rot_se|trans_se>.<other>".
void add_paired_at(repro::PairedFamily& family, const repro::KeyPath& prefix,
                   const AlignmentStudyOutcome& st);

PairedAtPoint paired_at(const repro::PairedFamily& family, const repro::KeyPath& prefix,
                        const AlignmentStudyOutcome& st);

// How many of `v` (Proposed against each other method) are significantly below (lower) or above (!lower).
int count_if_paired(const std::vector<repro::PairedComparison>& v, bool lower);

// Over points (sweep points, grid cells): where Proposed is significantly below every other method (best),
// above every other (worst), below or above at least one, in each error.
struct ProposedTally {
  int points = 0, best_rot = 0, worst_rot = 0, best_trans = 0, worst_trans = 0, best_both = 0;
  int below_some_rot = 0, above_some_rot = 0, below_some_trans = 0, above_some_trans = 0;
  void add(const PairedAtPoint& pp) {
    const int n = static_cast<int>(pp.others.size());
    const int br = count_if_paired(pp.rot, true), bt = count_if_paired(pp.trans, true);
    const int ar = count_if_paired(pp.rot, false), at = count_if_paired(pp.trans, false);
    ++points;
    best_rot += br == n, best_trans += bt == n, best_both += br == n && bt == n;
    worst_rot += ar == n, worst_trans += at == n;
    below_some_rot += br > 0, below_some_trans += bt > 0, above_some_rot += ar > 0,
        above_some_trans += at > 0;
  }
  void record(repro::Results& r) const {
    r.metric("proposed_best.rot_se", best_rot);
    r.metric("proposed_worst.rot_se", worst_rot);
    r.metric("proposed_best.trans_se", best_trans);
    r.metric("proposed_worst.trans_se", worst_trans);
    r.metric("proposed_below_some.rot_se", below_some_rot);
    r.metric("proposed_above_some.rot_se", above_some_rot);
    r.metric("proposed_below_some.trans_se", below_some_trans);
    r.metric("proposed_above_some.trans_se", above_some_trans);
  }
};

}  // namespace keel::study::ch3
