#include "align/certificate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <vector>

#include "core/timing.hpp"

namespace keel::align {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<CsRow> arc_rows(double a, double b) {
  const double m = 0.5 * (a + b), h = 0.5 * (b - a);
  std::vector<CsRow> rows;
  rows.push_back({std::cos(m), std::sin(m), std::cos(h), 1e300});  // beyond the chord
  for (double phi : {a, m, b}) rows.push_back({std::cos(phi), std::sin(phi), -1e300, 1.0});  // tangents
  return rows;
}

struct Node {
  double a, b, lb;
  bool operator<(const Node& o) const { return lb > o.lb || (lb == o.lb && a > o.a); }  // min-heap on lb
};

}  // namespace

void CertificateOptions::validate() const {
  if (!(relative_gap > 0))
    throw std::invalid_argument(
        fmt::format("CertificateOptions.relative_gap = {}: must be > 0", relative_gap));
  if (node_limit < 1) throw std::invalid_argument("CertificateOptions.node_limit = 0: must be >= 1");
  if (initial_intervals < 8)
    throw std::invalid_argument(
        fmt::format("CertificateOptions.initial_intervals = {}: must be >= 8", initial_intervals));
}

Certificate certify_rotation(const AlignmentProblem& p, const Regions& reg, const LpSettings& lp_settings,
                             const CertificateOptions& o) {
  o.validate();
  const auto t0 = core::Clock::now();
  LpSettings settings = lp_settings;
  settings.disc_tolerance = 0;
  HullLp lp(Parameterization::rotation_like, p.query_x, p.query_y, reg.planes, reg.boxes, settings);
  Certificate cert;
  cert.bound.upper = kInf;

  auto check = [](const LpSolution& s) {
    if (s.status == LpStatus::failed)
      throw std::runtime_error("certify_rotation: CLP did not prove optimality of an interval LP");
  };
  auto upper = [&](double theta) {  // stops as soon as θ provably cannot improve the incumbent
    lp.fix_cs(std::cos(theta), std::sin(theta));
    const LpSolution s = lp.solve(cert.bound.upper);
    lp.free_cs();
    check(s);
    cert.lp_solves += s.solves;
    if (s.status == LpStatus::optimal && s.cost < cert.bound.upper) {
      cert.bound.upper = s.cost, cert.theta = theta, cert.tx = s.params[2], cert.ty = s.params[3];
    }
  };
  // Lower bound over [a, b]; also tries the relaxed solution's angle as an upper bound.
  auto bound = [&](double a, double b) {
    lp.set_cs_rows(arc_rows(a, b));
    const LpSolution s = lp.solve();
    check(s);
    cert.lp_solves += s.solves;
    ++cert.nodes;
    if (s.status != LpStatus::optimal) return kInf;  // no rotation of the interval fits the boxes
    const double lb = s.cost;
    const double th = std::atan2(s.params[1], s.params[0]);
    upper(0.5 * (a + b));
    if (std::abs(std::remainder(th - 0.5 * (a + b), 2 * kPi)) > 1e-12) upper(th);
    return lb;
  };
  // core::Bound{lb, upper}'s gap within relative_gap (core/bound.hpp), written as a product.
  auto closed = [&](double lb) {
    return cert.bound.upper - lb <= o.relative_gap * std::max(1.0, std::abs(cert.bound.upper));
  };

  std::priority_queue<Node> open;
  double dropped = kInf;  // smallest bound of an interval dropped as within the gap
  const double w = 2 * kPi / o.initial_intervals;
  for (int k = 0; k < o.initial_intervals; ++k) {
    const double a = -kPi + k * w, b = a + w;
    const double lb = bound(a, b);
    if (lb < kInf) open.push({a, b, lb});
  }
  // (an initial interval is never dropped: every one is queued and split or closed below)
  cert.status = core::SearchStatus::optimal;
  while (!open.empty()) {
    const Node n = open.top();
    if (closed(n.lb)) break;  // every open interval is within the gap of the incumbent
    if (cert.nodes + 2 > o.node_limit) {
      cert.status = core::SearchStatus::node_limit;
      break;
    }
    open.pop();
    const double m = 0.5 * (n.a + n.b);
    for (auto [a, b] : {std::pair{n.a, m}, std::pair{m, n.b}}) {
      const double lb = std::max(n.lb, bound(a, b));  // a child's bound is at least its parent's
      if (lb < kInf && !closed(lb))
        open.push({a, b, lb});
      else
        dropped = std::min(dropped, lb);
    }
  }
  if (cert.bound.upper == kInf)
    throw std::runtime_error("certify_rotation: no rotation places every query point inside its box");
  cert.bound.lower = std::min({cert.bound.upper, dropped, open.empty() ? kInf : open.top().lb});
  cert.time_s = core::seconds_since(t0);
  return cert;
}

double rigid_objective(const AlignmentProblem& p, const Regions& reg, const LpSettings& lp_settings,
                       double theta) {
  LpSettings settings = lp_settings;
  settings.disc_tolerance = 0;
  HullLp lp(Parameterization::rotation_like, p.query_x, p.query_y, reg.planes, reg.boxes, settings);
  lp.fix_cs(std::cos(theta), std::sin(theta));
  const LpSolution s = lp.solve();
  if (s.status == LpStatus::failed) throw std::runtime_error("rigid_objective: CLP did not prove optimality");
  return s.status == LpStatus::optimal ? s.cost : kInf;
}

}  // namespace keel::align
