#include "app/marginals.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "core/timing.hpp"
#include "cov/information.hpp"

namespace keel::app {

namespace {

Marginals query(const cov::MarginalCovariance& mc, int dimension, const MarginalsRequest& r,
                const Progress& progress) {
  if (progress)
    progress(r.ids.empty()
                 ? fmt::format("joint marginals of {} pair{}", r.pairs.size(), r.pairs.size() == 1 ? "" : "s")
                 : fmt::format("joint marginal of {} poses", r.ids.size()));
  Marginals out;
  out.dimension = dimension;
  out.factor = mc.summary();
  const auto t0 = core::Clock::now();
  if (r.ids.empty()) {
    out.pairs = cov::pair_marginals(mc, r.pairs, r.threads);
  } else {
    out.joint = mc.joint(r.ids);
  }
  out.extraction_time_s = core::seconds_since(t0);
  return out;
}

void check_request(const MarginalsRequest& r, int gauge_pose, const Progress& progress) {
  if (r.pairs.empty() == r.ids.empty())
    throw std::invalid_argument("marginals: give exactly one of pairs and ids");
  if (progress)
    progress(fmt::format(
        "information matrix at the poses and its Cholesky factorization (gauge: pose {} fixed)", gauge_pose));
}

}  // namespace

namespace {

// The graph's gauge: its gauge pose (g2o's FIX line; pose 0 by default) held fixed.
template <class Graph>
cov::GaugeOptions gauge_of(const Graph& g) {
  cov::GaugeOptions gauge;
  gauge.pose = g.gauge_pose;
  return gauge;
}

}  // namespace

cov::MarginalCovariance factorize(const graph::PoseGraph2D& g, const pgo::Estimate2D& at,
                                  const cov::CovarianceOptions& options) {
  return cov::MarginalCovariance(cov::information_matrix(g, at.poses, at.landmarks, gauge_of(g)), options);
}

cov::MarginalCovariance factorize(const graph::PoseGraph3D& g, const pgo::Estimate3D& at,
                                  const cov::CovarianceOptions& options) {
  return cov::MarginalCovariance(cov::information_matrix(g, at.poses, gauge_of(g)), options);
}

Marginals marginals(const graph::PoseGraph2D& g, const pgo::Estimate2D& at, const MarginalsRequest& request,
                    const Progress& progress) {
  check_request(request, g.gauge_pose, progress);
  return query(factorize(g, at, request.covariance), 2, request, progress);
}

Marginals marginals(const graph::PoseGraph3D& g, const pgo::Estimate3D& at, const MarginalsRequest& request,
                    const Progress& progress) {
  check_request(request, g.gauge_pose, progress);
  return query(factorize(g, at, request.covariance), 3, request, progress);
}

}  // namespace keel::app
