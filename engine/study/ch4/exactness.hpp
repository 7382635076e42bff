#pragma once

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch4/segments.hpp"

namespace keel::study::ch4 {

// Theorems 4.5.3–4.5.4: is Sparse-BSOS at d = k = 1 exact? The counterexample of
// sos::exactness_counterexample and families of random small graphs, each solved at order 1 with escalation
// to order 2.
struct Exactness {
  struct Options {
    ExactnessOptions study;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    CertifiedSolution counterexample;
    ExactnessOutcome study;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
