#pragma once

#include "study/ch5/composition_setup.hpp"

namespace keel::study::ch5 {

// Figs. 5.5–5.6 (§5.7.2): the relative pose of two correlated poses; the covariance error ε of eq. 5.56 with
// and without the cross-covariance against the scale α of the covariances, and one example of the samples.
struct RelativePose {
  struct Options {
    double yaw = 0.0;  // radians (yaw_deg in the config)
    std::vector<double> t_g1, t_g2, marginal_diag, cross_diag, alphas;
    double example_alpha = 1.0, level = 0.95;
    int region_points = 1500;
    std::size_t samples = 10000;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<double> error_joint, error_independent, error_mc_noise;  // one per α
    RelativePoseOutcome example;                                         // at example_alpha, samples kept
  };
  // α_k's study runs on stream offset (2k) << 32 and its independent second Monte-Carlo set (the noise floor
  // of ε) on (2k + 1) << 32; the example on 1 << 40.
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch5
