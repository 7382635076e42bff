// The chapter-2 studies of the simulated 1D world (§2.7.1), one per experiment: World1DComparison (Fig. 2.2:
// every selector against the combinatorial maximum of eq. 2.5), DensitySweep (beyond Fig. 2.2: PCM's match
// rate as the worlds get denser) and Timing (Fig. 2.3: selection time against the number of measurements).
// Each has the study shape of repro/run.hpp; the machinery is world1d.hpp's.
#pragma once

#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch2/world1d.hpp"

namespace keel::study::ch2 {

// [params] of the 1D-world studies: the world model (with counts), PCM's and RANSAC's thresholds
// γ = χ²₁ quantile of 1 − p (dof 1: the 1D world) from pcm_p and ransac_p, SCGP's options, the combinatorial
// search and the number of worlds.
[[nodiscard]] World1DStudyOptions read_world1d_study(const core::ConfigTable& p);

// Fig. 2.2 (§2.7.1.1): PCM-Exact, PCM-Heuristic, SCGP and RANSAC against the combinatorial maximum pairwise
// consistent set (eq. 2.5) on simulated 1D worlds.
struct World1DComparison {
  struct Options {
    World1DStudyOptions study;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    World1DStudy study;
    CombinatorialComparison comparison;  // PCM-Exact, PCM-Heuristic, SCGP, RANSAC, in that order
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Beyond Fig. 2.2: PCM-Heuristic's and PCM-Exact's rate of returning a set of the combinatorial maximum's
// size as the outliers are drawn closer to the true state, every density on the same streams.
struct DensitySweep {
  struct Options {
    World1DStudyOptions study;            // only the combinatorial search and PCM run
    std::vector<double> ranges;           // outlier mean ranges R
    double reference_heuristic_rate = 0;  // Fig. 2.2's PCM-Heuristic rate, drawn as a reference line
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<double> heuristic, exact, max_size;  // one per range
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Fig. 2.3 (§2.7.1.2): the median selection time of every selector against the number of measurements m.
struct Timing {
  struct Options {
    TimingSweepOptions sweep;
    std::vector<double> sizes;  // as given (the series of the sweep)
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    TimingSweep sweep;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch2
