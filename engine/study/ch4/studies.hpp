// The chapter-4 studies (§4.5–4.6), one per experiment: Segments (Figs. 4.2–4.5: SBSOS-SLAM against
// Levenberg–Marquardt on the segments of a planar data set), FirstSegment (Fig. 4.1: the first 430 poses of
// CityTrees10000), Exactness (Theorems 4.5.3–4.5.4 tested on random small graphs and a counterexample) and
// WholeDataCertificate (beyond the thesis: the dual certificate of LM's solution of a whole data set). Each
// has the study shape of repro/run.hpp; the machinery is segments.hpp's.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "pgo/optimize.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch4/segments.hpp"

namespace keel::study::ch4 {

// Figs. 4.2–4.5 (§4.6): every segment of a planar data set by SBSOS with its certificate and by LM from a
// random and from an odometry start; errors against ground truth, costs on the thesis's cost.
struct Segments {
  struct Options {
    PlanarDatasetFiles data;
    SegmentStudyOptions study;
    std::string errors_figure, errors_title;    // the error CDFs (Fig. 4.3 / 4.4): file name and title
    std::string example_figure, example_title;  // the worst segment drawn (Fig. 4.2 / 4.5)
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    bool landmarks = false;  // the data set has landmarks (their errors are recorded)
    SegmentStudyOutcome study;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

// Fig. 4.1 (§4.6): the first segment of CityTrees10000 (430 poses, 40 landmarks) by SBSOS and by LM from the
// random start the figure shows.
struct FirstSegment {
  using Options = Segments::Options;
  struct Outcome {
    Options options;
    SegmentOutcome segment;
    pgo::Estimate2D start;  // LM's random start on the segment, in the frame of its pose 0
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

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

// Beyond the thesis: LM's solution of whole planar data sets (from odometry and from a random start), refined
// on the thesis's cost and certified, or refused, by its dual certificate (sos/verify.hpp).
struct WholeDataCertificate {
  struct Options {
    std::vector<std::pair<std::string, std::string>> files;  // (data set, graph file)
    GlobalCertificateStudyOptions study;
    static Options read(const core::ConfigTable& p);
  };
  struct Outcome {
    Options options;
    GlobalCertificateStudyOutcome study;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch4
