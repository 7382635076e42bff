#include "study/ch3/comparison.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "align/sdp.hpp"
#include "core/parallel.hpp"
#include "core/statistics.hpp"
#include "core/timing.hpp"

namespace keel::study::ch3 {

using namespace keel::align;

namespace {
constexpr double kPi = 3.14159265358979323846;
double wrap(double a) { return std::remainder(a, 2 * kPi); }

}  // namespace

AlignmentProblem problem_of(const sim::AlignmentWorld& w) {
  AlignmentProblem p;
  p.ref_x = w.ref_x, p.ref_y = w.ref_y;
  p.query_x = w.query_x, p.query_y = w.query_y;
  p.dissimilarity = euclidean_dissimilarity(w.ref_features, w.query_features, w.feature_dim);
  return p;
}

AlignmentProblem problem_of(const sim::HullWorld& w) {
  AlignmentProblem p;
  p.ref_x = w.ref_x, p.ref_y = w.ref_y, p.ref_z = w.ref_z;
  p.query_x = w.query_x, p.query_y = w.query_y, p.query_z = w.query_z;
  p.dissimilarity = euclidean_dissimilarity(w.ref_features, w.query_features, w.feature_dim);
  return p;
}

EstimateScore score_estimate(const AlignmentProblem& p, const Transform2& a, double theta, double tx,
                             double ty, double valid_tolerance) {
  EstimateScore e;
  double cx = 0, cy = 0;
  for (std::size_t j = 0; j < p.query_size(); ++j) cx += p.query_x[j], cy += p.query_y[j];
  cx /= static_cast<double>(p.query_size()), cy /= static_cast<double>(p.query_size());
  e.rot_error = wrap(project_to_rigid(a, cx, cy).theta - theta);
  e.rot_se = e.rot_error * e.rot_error;
  const double ea = wrap(std::atan2(a.a21, a.a11) - theta);
  e.rot_se_atan2 = ea * ea;
  const double ex = a.a11 * cx + a.a12 * cy + a.tx, ey = a.a21 * cx + a.a22 * cy + a.ty;
  const double c = std::cos(theta), s = std::sin(theta);
  const double gx = c * cx - s * cy + tx, gy = s * cx + c * cy + ty;
  e.trans_se = (ex - gx) * (ex - gx) + (ey - gy) * (ey - gy);
  e.trans_se_origin = (a.tx - tx) * (a.tx - tx) + (a.ty - ty) * (a.ty - ty);
  singular_values(a, e.singular_max, e.singular_min);
  e.radius = std::hypot(a.a11, a.a21);
  e.valid = approximately_valid(a, valid_tolerance);
  return e;
}

MethodOutcome score_alignment(const AlignmentProblem& p, const AlignResult& r, double theta, double tx,
                              double ty, double valid_tolerance) {
  MethodOutcome o;
  o.raw = r.raw;
  o.rigid = r.rigid;
  o.cost = r.cost;
  o.sector = r.sector;
  o.rounds = static_cast<int>(r.rounds.size());
  for (const auto& t : r.rounds) o.lp_solves += t.solves;
  o.final_score = score_estimate(p, r.raw, theta, tx, ty, valid_tolerance);
  // r.rigid keeps the centroid where r.raw puts it, so its angle is the polar projection scored above.
  o.rot_se = o.final_score.rot_se;
  o.trans_se = o.final_score.trans_se;
  o.singular_min = o.final_score.singular_min, o.singular_max = o.final_score.singular_max;
  o.valid = o.final_score.valid;
  for (const auto& t : r.rounds) {
    EstimateScore e = score_estimate(p, t.transform, theta, tx, ty, valid_tolerance);
    e.half_width = t.half_width;
    o.round_scores.push_back(e);
  }
  o.time_s = r.time_s;
  return o;
}

void ComparisonOptions::validate() const {
  align.validate();
  certificate.validate();
  if (methods.empty()) throw std::invalid_argument("ComparisonOptions.methods: empty");
  if (!(valid_tolerance > 0 && valid_tolerance < 1))
    throw std::invalid_argument(
        fmt::format("ComparisonOptions.valid_tolerance = {}: must be in (0, 1)", valid_tolerance));
  if (certify && std::find(methods.begin(), methods.end(), Method::proposed) == methods.end())
    throw std::invalid_argument("ComparisonOptions.certify: needs the proposed method among the methods");
}

void AlignmentStudyOptions::validate() const {
  world.validate();
  compare.validate();
  if (worlds < 1) throw std::invalid_argument("AlignmentStudyOptions.worlds = 0: must be >= 1");
}

namespace {

// SOConvHull's round 0 by the LP with tangent cuts and by DSDP.
SdpCheck sdp_check(const AlignmentProblem& p, const Regions& global, const AlignOptions& ao) {
  SdpCheck chk;
  LpSettings s = ao.lp;
  s.disc_tolerance = ao.disc_tolerance;
  const auto tl = core::Clock::now();
  HullLp lp(Parameterization::rotation_like, p.query_x, p.query_y, global.planes, global.boxes, s);
  const LpSolution cuts = lp.solve();
  chk.lp_time_s = core::seconds_since(tl);
  if (cuts.status != LpStatus::optimal) throw std::runtime_error("SOConvHull LP check: not optimal");
  chk.lp_cost = cuts.cost;
  const SdpSolution sdp = so_conv_hull_sdp(p, global);
  chk.sdp_cost = sdp.cost, chk.sdp_time_s = sdp.time_s, chk.sdp_converged = sdp.converged;
  return chk;
}

// The certificate of round 0 and the score of the proposed method's round-0 answer against it.
CertificateOutcome certificate_of(const AlignmentProblem& p, const Regions& global, const AlignOptions& ao,
                                  const AlignResult& proposed, const CertificateOptions& options) {
  CertificateOutcome c;
  c.certificate = certify_rotation(p, global, ao.lp, options);
  const Transform2& t0 = proposed.rounds.front().transform;
  c.sector_theta = std::atan2(t0.a21 - t0.a12, t0.a11 + t0.a22);
  c.sector_objective = rigid_objective(p, global, ao.lp, c.sector_theta);
  const double f = c.certificate.bound.upper;
  c.relative_gap = (c.sector_objective - f) / std::max(1.0, std::abs(f));
  c.theta_difference = std::abs(wrap(c.sector_theta - c.certificate.theta));
  return c;
}

}  // namespace

AlignmentStudyOutcome compare_methods(const ComparisonOptions& o, std::size_t worlds,
                                      const repro::RunContext& context,
                                      const std::function<WorldTruth(std::size_t)>& world,
                                      core::Progress* progress) {
  o.validate();
  AlignmentStudyOutcome out;
  out.methods = o.methods;
  const std::size_t nm = o.methods.size();
  out.outcomes.assign(nm, std::vector<MethodOutcome>(worlds));
  out.world_theta.resize(worlds);
  out.reference_points.resize(worlds);
  out.query_points.resize(worlds);
  if (o.certify) out.certificates.resize(worlds);
  out.sdp_checks.resize(std::min(o.sdp_check_worlds, worlds));
  // One trial per world; its record is everything the world wrote (all plain structs).
  const auto save = [&](repro::Writer& wr, std::size_t w) {
    repro::save(wr, std::tie(out.world_theta[w], out.reference_points[w], out.query_points[w]));
    for (std::size_t m = 0; m < nm; ++m) repro::save(wr, out.outcomes[m][w]);
    if (o.certify) repro::save(wr, out.certificates[w]);
    if (w < out.sdp_checks.size()) repro::save(wr, out.sdp_checks[w]);
  };
  const auto load = [&](repro::Reader& rd, std::size_t w) {
    auto head = std::tie(out.world_theta[w], out.reference_points[w], out.query_points[w]);
    repro::load(rd, head);
    for (std::size_t m = 0; m < nm; ++m) repro::load(rd, out.outcomes[m][w]);
    if (o.certify) repro::load(rd, out.certificates[w]);
    if (w < out.sdp_checks.size()) repro::load(rd, out.sdp_checks[w]);
  };
  context.trials(
      worlds,
      [&](std::size_t w) {
        const WorldTruth truth = world(w);
        const AlignmentProblem& p = truth.problem;
        out.world_theta[w] = truth.theta;
        out.reference_points[w] = p.reference_size();
        out.query_points[w] = p.query_size();
        AlignOptions ao = o.align;
        ao.threads = 1;
        const auto th = core::Clock::now();
        const Regions global = global_regions(p, ao);
        const double hull_time = core::seconds_since(th);
        if (w < out.sdp_checks.size()) out.sdp_checks[w] = sdp_check(p, global, ao);
        align::HullCache cache(ao.hull);  // later rounds' hulls shared by the methods, each charged in full
        for (std::size_t m = 0; m < nm; ++m) {
          ao.method = o.methods[m];
          const AlignResult r = align::align(p, ao, &global, &cache);
          MethodOutcome mo = score_alignment(p, r, truth.theta, truth.tx, truth.ty, o.valid_tolerance);
          mo.time_s += hull_time;
          out.outcomes[m][w] = mo;
          if (o.certify && ao.method == Method::proposed)
            out.certificates[w] = certificate_of(p, global, ao, r, o.certificate);
        }
      },
      save, load, progress);
  return out;
}

AlignmentStudyOutcome run_alignment_study(const AlignmentStudyOptions& o, const repro::RunContext& context,
                                          core::Progress* progress) {
  o.validate();
  const core::Streams& streams = context.streams();
  return compare_methods(
      o.compare, o.worlds, context,
      [&](std::size_t w) {
        const sim::AlignmentWorld world =
            sim::make_alignment_world(o.world, streams.seed(), streams.index(w));
        return WorldTruth{problem_of(world), world.theta, world.tx, world.ty};
      },
      progress);
}

FencedSummary fenced_summary(std::vector<double> v) {
  FencedSummary s;
  s.n = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = core::quantile_sorted(v, 0.5);
  const double q1 = core::quantile_sorted(v, 0.25), q3 = core::quantile_sorted(v, 0.75), iqr = q3 - q1;
  const double lo = q1 - 1.5 * iqr, hi = q3 + 1.5 * iqr;
  std::vector<double> kept;
  for (double x : v) {
    s.mean += x;
    if (x >= lo && x <= hi) kept.push_back(x);
  }
  s.mean /= static_cast<double>(v.size());
  s.dropped = v.size() - kept.size();
  if (kept.size() > 1) {
    double m = 0;
    for (double x : kept) m += x;
    m /= static_cast<double>(kept.size());
    for (double x : kept) s.std += (x - m) * (x - m);
    s.std = std::sqrt(s.std / static_cast<double>(kept.size() - 1));
  }
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// The hull substitute of §3.8

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
  return feature_scales(w.ref_features, w.feature_dim);
}

AlignmentProblem standardized_problem_of(const sim::HullWorld& w) {
  const std::vector<double> scale = reference_feature_scales(w);
  AlignmentProblem p;
  p.ref_x = w.ref_x, p.ref_y = w.ref_y, p.ref_z = w.ref_z;
  p.query_x = w.query_x, p.query_y = w.query_y, p.query_z = w.query_z;
  p.dissimilarity =
      euclidean_dissimilarity(standardize_features(w.ref_features, scale),
                              standardize_features(w.query_features, scale), static_cast<int>(scale.size()));
  return p;
}

void HullStudyOptions::validate() const {
  world.validate();
  compare.validate();
  if (worlds < 1) throw std::invalid_argument("HullStudyOptions.worlds = 0: must be >= 1");
}

HullStudyOutcome run_hull_study(const HullStudyOptions& o, const repro::RunContext& context,
                                core::Progress* progress) {
  o.validate();
  const core::Streams& streams = context.streams();
  return compare_methods(
      o.compare, o.worlds, context,
      [&](std::size_t w) {
        const sim::HullWorld world = sim::make_hull_world(o.world, streams.seed(), streams.index(w));
        return WorldTruth{standardized_problem_of(world), world.theta, world.tx, world.ty};
      },
      progress);
}

}  // namespace keel::study::ch3
