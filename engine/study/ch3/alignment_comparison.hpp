#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/grading.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
#include "sim/terrain.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

// Table 3.1 (§3.7): the four convex alignment methods on simulated worlds, errors summarised as the thesis
// does (median; std after 1.5·IQR fences); beyond the thesis, the certificate of round 0 on every world.
struct AlignmentComparison {
  struct Options {
    AlignmentStudyOptions study;
    double near_gap = 1e-3;  // certificate.within_<gap>_rate: round 0's answer this close to the optimum
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    AlignmentStudyOutcome study;
    // [world] its spatial block, for worlds that share data (overlapping terrain windows: the paired
    // comparisons then take one value per block); empty when the worlds are independent draws.
    std::vector<std::size_t> blocks;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Table 3.1's paired comparisons (the four columns, Proposed minus each other method, and the two medians at
// every round) added to `family`, and the table's records read from it after Holm's correction:
// AlignmentComparison's record, and TerrainComparison's on real terrain.
void add_table_comparisons(repro::PairedFamily& family, const AlignmentComparison::Outcome& outcome);
void record_table(repro::Results& r, const AlignmentComparison::Outcome& outcome,
                  const repro::PairedFamily& family);

}  // namespace keel::study::ch3
