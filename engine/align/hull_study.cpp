#include "align/hull_study.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/parallel.hpp"

namespace keel::align {

std::vector<double> reference_feature_scales(const sim::HullWorld& w) {
  const std::size_t na = w.ref_x.size();
  if (w.feature_dim < 1)
    throw std::invalid_argument(fmt::format("reference_feature_scales: feature_dim = {}", w.feature_dim));
  const auto d = static_cast<std::size_t>(w.feature_dim);
  if (na == 0) throw std::invalid_argument("reference_feature_scales: the reference has no position");
  if (w.ref_features.size() != na * d || w.query_features.size() != w.query_x.size() * d)
    throw std::invalid_argument(fmt::format(
        "reference_feature_scales: {} reference and {} query feature values for {} and {} positions of "
        "dimension {}",
        w.ref_features.size(), w.query_features.size(), na, w.query_x.size(), d));
  std::vector<double> scale(d, 0.0);
  for (std::size_t k = 0; k < d; ++k) {
    double mean = 0;
    for (std::size_t i = 0; i < na; ++i) mean += w.ref_features[i * d + k];
    mean /= static_cast<double>(na);
    double ss = 0;
    for (std::size_t i = 0; i < na; ++i) {
      const double e = w.ref_features[i * d + k] - mean;
      ss += e * e;
    }
    scale[k] = std::sqrt(ss / static_cast<double>(na));
  }
  return scale;
}

AlignmentProblem standardized_problem_of(const sim::HullWorld& w) {
  const std::vector<double> scale = reference_feature_scales(w);
  const std::size_t d = scale.size();
  auto standardise = [&](std::vector<double> f) {
    for (std::size_t n = 0; n < f.size(); ++n) {
      const double s = scale[n % d];
      if (s > 0 && std::isfinite(s)) f[n] /= s;
    }
    return f;
  };
  AlignmentProblem p;
  p.ref_x = w.ref_x, p.ref_y = w.ref_y, p.ref_z = w.ref_z;
  p.query_x = w.query_x, p.query_y = w.query_y, p.query_z = w.query_z;
  p.dissimilarity = euclidean_dissimilarity(standardise(w.ref_features), standardise(w.query_features),
                                            static_cast<int>(d));
  return p;
}

void HullStudyOptions::validate() const {
  world.validate();
  compare.validate();
  if (worlds < 1) throw std::invalid_argument("HullStudyOptions.worlds = 0: must be >= 1");
}

HullStudyOutcome run_hull_study(const HullStudyOptions& o, core::Progress* progress) {
  o.validate();
  return compare_methods(
      o.compare, o.worlds, o.threads,
      [&](std::size_t w) {
        const sim::HullWorld world = sim::make_hull_world(o.world, o.seed, o.stream_base + w);
        return WorldTruth{standardized_problem_of(world), world.theta, world.tx, world.ty};
      },
      progress);
}

}  // namespace keel::align
