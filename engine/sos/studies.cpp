#include "sos/studies.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/parallel.hpp"
#include "core/random.hpp"
#include "repro/shard.hpp"
#include "core/timing.hpp"
#include "pgo/optimize.hpp"

namespace keel::sos {

namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap(double a) { return std::remainder(a, 2.0 * kPi); }

// Errors and cost of an estimate given in any gauge: re-expressed in the frame of its pose 0 first.
MethodOutcome score(const PlanarProblem& p, const std::vector<lie::SE2>& poses,
                    const std::vector<lie::Vec2>& lms, const std::vector<lie::SE2>& truth,
                    const std::vector<lie::Vec2>& truth_lms, double time_s) {
  MethodOutcome m;
  m.time_s = time_s;
  const lie::SE2 inv0 = poses[0].inverse();
  for (const auto& t : poses) m.poses.push_back(inv0 * t);
  for (const auto& l : lms) m.landmarks.push_back(inv0.act(l));
  m.cost = polynomial_cost(p, unknowns_of(p, m.poses, m.landmarks));
  if (!truth.empty()) {
    for (std::size_t i = 0; i < m.poses.size(); ++i) {
      m.trans_error += (m.poses[i].translation() - truth[i].translation()).norm();
      m.rot_error += std::abs(wrap(m.poses[i].angle() - truth[i].angle()));
    }
    m.trans_error /= static_cast<double>(m.poses.size());
    m.rot_error /= static_cast<double>(m.poses.size());
  }
  if (!truth_lms.empty() && !m.landmarks.empty()) {
    for (std::size_t l = 0; l < m.landmarks.size(); ++l)
      m.landmark_error += (m.landmarks[l] - truth_lms[l]).norm();
    m.landmark_error /= static_cast<double>(m.landmarks.size());
  }
  return m;
}

}  // namespace

void SegmentStudyOptions::validate() const {
  if (segment_length < 2)
    throw std::invalid_argument(
        fmt::format("sos::SegmentStudyOptions: segment_length must be >= 2 (got {})", segment_length));
  if (stride < 1)
    throw std::invalid_argument(
        fmt::format("sos::SegmentStudyOptions: stride must be >= 1 (got {})", stride));
  if (max_segments < 0)
    throw std::invalid_argument(
        fmt::format("sos::SegmentStudyOptions: max_segments must be >= 0 (got {})", max_segments));
  if (!(random_extent > 0))
    throw std::invalid_argument(
        fmt::format("sos::SegmentStudyOptions: random_extent must be > 0 (got {})", random_extent));
  sbsos.validate();
  lm.validate();
}

SegmentStudyOutcome run_segment_study(const graph::PoseGraph2D& graph, const std::vector<lie::SE2>& truth,
                                      const std::vector<lie::Vec2>& truth_landmarks,
                                      const SegmentStudyOptions& o, core::Progress* progress) {
  o.validate();
  const int n = static_cast<int>(graph.poses.size());
  if (!truth.empty() && static_cast<int>(truth.size()) != n)
    throw std::invalid_argument(
        fmt::format("sos::run_segment_study: {} ground-truth poses for a graph of {}", truth.size(), n));
  int count = n >= o.segment_length ? (n - o.segment_length) / o.stride + 1 : 0;
  if (o.max_segments > 0) count = std::min(count, o.max_segments);
  if (count == 0)
    throw std::invalid_argument(
        fmt::format("sos::run_segment_study: no segment of {} poses fits in {} poses", o.segment_length, n));
  SegmentStudyOutcome out;
  out.segments.resize(static_cast<std::size_t>(count));
  repro::trial_loop(  // one trial per segment; its record is the SegmentOutcome
      static_cast<std::size_t>(count),
      [&](std::size_t k) {
        SegmentOutcome& s = out.segments[k];
        s.first = static_cast<int>(k) * o.stride;
        s.poses = o.segment_length;
        Segment seg;
        PlanarProblem p;
        try {  // a segment that cannot be cut or posed is a failed row, not the end of the study
          seg = extract_segment(graph, s.first, o.segment_length, truth, truth_landmarks);
          s.edges = static_cast<int>(seg.graph.edges.size());
          s.landmarks = static_cast<int>(seg.graph.landmarks.size());
          s.landmark_measurements = static_cast<int>(seg.graph.landmark_measurements.size());
          s.truth = seg.truth_poses;
          s.truth_landmarks = seg.truth_landmarks;
          p = planar_problem(seg.graph);
        } catch (const std::exception& e) {
          s.failed = true;
          s.error = e.what();
          return;
        }
        try {
          const CertifiedSolution c = solve_certified(seg.graph, p, o.sbsos);
          s.sbsos = score(p, c.estimate.poses, c.estimate.landmarks, s.truth, s.truth_landmarks, c.time_s);
          s.status = c.status;
          s.certified_order = c.certified_order;
          s.relative_gap = c.relative_gap();
          s.rank_ratio = c.first.rank_ratio;
          s.lower_bound = c.bound.lower;
          s.primal_residual = c.first.primal_residual;
          s.s_min_eigenvalue = c.first.s_min_eigenvalue;
          s.solver_claims_optimal = c.first.solver_claims_optimal;
          s.escalated = c.escalated;
          s.note = c.note;
          s.sdp_time_s = c.first.solver_time_s;
        } catch (const std::exception& e) {
          s.failed = true;
          s.error = e.what();
        }
        for (int which = 0; which < 2; ++which) {
          pgo::Options lm = o.lm;
          lm.constant_poses = {0};
          if (which == 0) {
            lm.initial_guess = pgo::InitialGuess::random;
            lm.seed = o.seed + k;
            lm.random_extent = o.random_extent;
          } else {
            lm.initial_guess = pgo::InitialGuess::as_read;  // the segment's poses are chained odometry
          }
          const auto t0 = core::Clock::now();
          const pgo::Result2D r = pgo::optimize(seg.graph, lm);
          const double dt = core::seconds_since(t0);
          (which == 0 ? s.lm_random : s.lm_odometry) =
              score(p, r.estimate.poses, r.estimate.landmarks, s.truth, s.truth_landmarks, dt);
        }
      },
      o.threads, progress, out.segments);
  return out;
}

void ExactnessOptions::validate() const {
  if (families.empty()) throw std::invalid_argument("sos::ExactnessOptions: no families");
  for (const auto& f : families) {
    if (f.poses < 2 || f.trials < 1 || f.edge_probability < 0 || f.edge_probability > 1 || f.extent < 0 ||
        f.translation_noise < 0 || (!f.uniform_rotations && f.rotation_noise < 0))
      throw std::invalid_argument(
          fmt::format("sos::ExactnessFamily '{}': needs poses >= 2, trials >= 1, edge_probability in [0, 1], "
                      "extent >= 0 and noise >= 0",
                      f.name));
  }
  certify.validate();
}

graph::PoseGraph2D exactness_counterexample() {
  const double theta[6] = {0.23, 0.43, 1.13, -1.81, 1.36, -1.35};
  const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  graph::PoseGraph2D g;
  g.poses.assign(4, lie::SE2::identity());
  for (int k = 0; k < 6; ++k) {
    graph::Edge2 e;
    e.i = pairs[k][0], e.j = pairs[k][1];
    e.measurement = lie::SE2(0, 0, theta[k]);
    e.information = lie::Mat3(Eigen::Vector3d(1, 1, 2).asDiagonal());  // ω_R = ω_x = ω_y = 1 (problem.hpp)
    g.edges.push_back(e);
  }
  g.source = "exactness counterexample";
  return g;
}

ExactnessOutcome run_exactness_study(const ExactnessOptions& o, core::Progress* progress) {
  o.validate();
  ExactnessOutcome out;
  std::vector<std::pair<std::size_t, std::size_t>> jobs;
  for (std::size_t f = 0; f < o.families.size(); ++f) {
    out.trials.emplace_back(static_cast<std::size_t>(o.families[f].trials));
    for (int t = 0; t < o.families[f].trials; ++t) jobs.emplace_back(f, static_cast<std::size_t>(t));
  }
  // One trial per (family, trial) job; its record is the ExactnessTrial.
  const auto save = [&](repro::Writer& w, std::size_t j) {
    repro::save(w, out.trials[jobs[j].first][jobs[j].second]);
  };
  const auto load = [&](repro::Reader& r, std::size_t j) {
    repro::load(r, out.trials[jobs[j].first][jobs[j].second]);
  };
  repro::trial_loop(
      jobs.size(),
      [&](std::size_t j) {
        const auto [f, t] = jobs[j];
        const ExactnessFamily& fam = o.families[f];
        core::Rng rng = core::Rng::stream(o.seed, (static_cast<std::uint64_t>(f) << 20) + t);
        std::vector<lie::SE2> truth;
        for (int i = 0; i < fam.poses; ++i)
          truth.emplace_back(rng.uniform(0, fam.extent), rng.uniform(0, fam.extent), rng.uniform(-kPi, kPi));
        graph::PoseGraph2D g;
        g.poses = truth;
        for (int i = 0; i < fam.poses; ++i)
          for (int k = i + 1; k < fam.poses; ++k) {
            if (k != i + 1 && rng.uniform() >= fam.edge_probability) continue;
            const lie::SE2 z =
                truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(k)];
            const double th = fam.uniform_rotations ? rng.uniform(-kPi, kPi)
                                                    : z.angle() + fam.rotation_noise * rng.normal();
            graph::Edge2 e;
            e.i = i, e.j = k;
            e.measurement = lie::SE2(z.translation().x() + fam.translation_noise * rng.normal(),
                                     z.translation().y() + fam.translation_noise * rng.normal(), th);
            e.information = lie::Mat3(Eigen::Vector3d(1, 1, 2).asDiagonal());
            g.edges.push_back(e);
          }
        const CertifiedSolution c = solve_certified(g, o.certify);
        ExactnessTrial& r = out.trials[f][t];
        r.gap_order1 = std::isfinite(c.first.lower_bound)
                           ? std::max(0.0, c.bound.upper - c.first.lower_bound) / std::max(c.bound.upper, 1.0)
                           : std::numeric_limits<double>::infinity();
        r.tight_order1 =
            c.certified_order == 1;  // the certificate's verdict (finite, valid bound within tolerance)
        r.certified = c.status == core::SearchStatus::optimal;
        r.escalated = c.escalated;
        r.escalation_skipped = !r.tight_order1 && !c.escalated;
        r.rank_ratio = c.first.rank_ratio;
      },
      save, load, o.threads, progress);
  return out;
}

}  // namespace keel::sos
