// The chapter-5 studies of composed and relative poses (§5.5.2, §5.7.2, §5.8.1, §5.9.1), one per thesis
// figure: Composition (Fig. 5.4), RelativePose (Figs. 5.5–5.6), UnscentedSsc (Fig. 5.7), LengthSweep
// (Fig. 5.8) and NoiseSweep (Fig. 5.9). Each has the study shape of repro/run.hpp; the Monte Carlo is
// simulate.hpp's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch5/simulate.hpp"

namespace keel::study::ch5 {

// [params] of a composition study: sigma_t, sigma_r, rho (eq. 5.41 and the AR(1) correlation), level (the one
// probability level scored, in levels[0]) and trajectories; also steps (N) when `with_steps`. Validated.
[[nodiscard]] CompositionSetup read_composition_setup(const core::ConfigTable& p, bool with_steps);

// Fig. 5.4 (§5.5.2): N correlated steps composed end to end; the fraction of Monte-Carlo end poses inside
// each predicted ellipsoid, and the regions' planar shadows.
struct Composition {
  struct Options {
    CompositionSetup setup;  // keep_samples is set by run (the figure draws the samples)
    int region_points = 1500;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    CompositionOutcome composition;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Fig. 5.7 (§5.8.1, eqs. 5.60–5.62): Fig. 5.4's SSC head-to-tail prediction converted to the Lie algebra by
// the unscented transform, against the true spread of the composed poses.
struct UnscentedSsc {
  using Options = Composition::Options;
  struct Outcome {
    Options options;
    CompositionOutcome composition;
    SscConversion conversion;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Fig. 5.8 (§5.9.1): the inside fractions against the number of composed poses N, every N on the same streams
// (common random numbers).
struct LengthSweep {
  struct Options {
    CompositionSetup setup;  // steps is set per sweep point
    int steps_min = 1, steps_max = 50, steps_stride = 1;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    std::vector<double> steps;                                  // N of each sweep point
    std::vector<double> ssc, ssc_independent, lie_independent;  // inside fractions at levels[0], one per N
    std::vector<double> lie_joint, lie_fourth_order;
    std::vector<double> steps_joint_fourth_order, lie_joint_fourth_order;  // where it was evaluated
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Fig. 5.9 (§5.9.1): the inside fractions against rotation noise (σt fixed) and against translation noise (σr
// fixed); each sweep on its own streams, common within it.
struct NoiseSweep {
  struct Options {
    CompositionSetup setup;  // sigma_t and sigma_r are set per sweep point
    double fixed_sigma = 3.0;
    std::vector<double> sigmas;
    static Options read(const core::ConfigTable& p);
  };
  struct Sweep {
    std::vector<double> ssc, ssc_independent, lie_independent, lie_joint, lie_fourth_order,
        lie_joint_fourth_order;  // one per σ
  };
  struct Outcome {
    Options options;
    Sweep rotation, translation;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

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
