#pragma once

#include <string>

#include "study/ch5/pairs.hpp"

namespace keel::study::ch5 {

// Table 5.1 and Figs. 5.10–5.14 (a–e): ε of eq. 5.56 with and without the cross-covariance of the two poses.
struct PairCorrelation {
  struct Options {
    PairsSetup pairs;
    PairStudySetup simulation;  // samples
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    SolvedPairs solved;
    std::vector<PairRecord> records;  // one per pair
    double monte_carlo_time_s = 0;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Shared with PairsVsSsc, which runs the same study: `<name>.mean` / `<name>.std` over all pairs and per
// offset
// (`offset<k>.<name>.mean`), and one panel of Figs. 5.10–5.14 (every pair at `offset` as a segment between
// the two positions, coloured by `field` on [0, vmax] with `cmap`).
PairStatistics record_statistics(repro::Results& r, const PairCorrelation::Outcome& s,
                                 double PairRecord::* field, const repro::KeyPath& name);
repro::Panel pair_panel(const PairCorrelation::Outcome& s, int offset, double PairRecord::* field,
                        const std::string& title, const std::string& cmap, double vmax);

}  // namespace keel::study::ch5
