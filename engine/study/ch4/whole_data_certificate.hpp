#pragma once

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch4/segments.hpp"

namespace keel::study::ch4 {

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
