#include "study/ch4/segments.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/parallel.hpp"
#include "core/random.hpp"
#include "core/timing.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "graph/trajectory.hpp"
#include "pgo/optimize.hpp"

namespace keel::study::ch4 {

using namespace keel::sos;

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
                                      const SegmentStudyOptions& o, const repro::RunContext& context,
                                      core::Progress* progress) {
  o.validate();
  const int n = static_cast<int>(graph.poses.size());
  if (!truth.empty() && static_cast<int>(truth.size()) != n)
    throw std::invalid_argument(
        fmt::format("run_segment_study: {} ground-truth poses for a graph of {}", truth.size(), n));
  int count = n >= o.segment_length ? (n - o.segment_length) / o.stride + 1 : 0;
  if (o.max_segments > 0) count = std::min(count, o.max_segments);
  if (count == 0)
    throw std::invalid_argument(
        fmt::format("run_segment_study: no segment of {} poses fits in {} poses", o.segment_length, n));
  SegmentStudyOutcome out;
  out.segments.resize(static_cast<std::size_t>(count));
  context.trials(  // one trial per segment; its record is the SegmentOutcome
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
            lm.seed = context.streams().seed() + k;
            lm.random_extent = o.random_extent;
          } else {
            lm.initial_guess = pgo::InitialGuess::as_read;  // the segment's poses are chained odometry
          }
          const auto t0 = core::Clock::now();
          const pgo::Result2D r = pgo::optimize(seg.graph, lm);
          const double dt = core::seconds_since(t0);
          MethodOutcome& m = which == 0 ? s.lm_random : s.lm_odometry;
          m = score(p, r.estimate.poses, r.estimate.landmarks, s.truth, s.truth_landmarks, dt);
          m.iterations = r.summary.iterations;
          m.converged = r.summary.termination == pgo::Termination::converged;
        }
      },
      progress, out.segments);
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
  if (multistart_starts < 1)
    throw std::invalid_argument(
        fmt::format("sos::ExactnessOptions.multistart_starts must be >= 1 (got {})", multistart_starts));
  certify.validate();
  multistart_refine.validate();
  dual.validate();
}

namespace {

// The lowest f over Newton runs on f (refine_solution) from `starts` random starts: every angle uniform on
// the circle, every translation zero (f is quadratic in the translations, so Newton's first step solves them
// for the start's rotations). Independent of the relaxation: no start uses its answer.
struct MultistartMinimum {
  double cost = std::numeric_limits<double>::infinity();
  Eigen::VectorXd z;
  int hits = 0;  // starts within 1e-8 relative of the lowest cost
};
MultistartMinimum multistart_minimum(const PlanarProblem& p, int starts, const RefineOptions& refine,
                                     core::Rng& rng) {
  MultistartMinimum m;
  std::vector<double> costs;
  for (int k = 0; k < starts; ++k) {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(p.unknowns());
    for (int node = 0; node < p.pose_nodes(); ++node) {
      const double th = rng.uniform(-kPi, kPi);
      z[4 * node] = std::cos(th), z[4 * node + 1] = std::sin(th);
    }
    (void)refine_solution(p, z, refine);
    const double f = polynomial_cost(p, z);
    costs.push_back(f);
    if (f < m.cost) m.cost = f, m.z = z;
  }
  for (double f : costs) m.hits += f <= m.cost + 1e-8 * std::max(m.cost, 1.0);
  return m;
}

}  // namespace

ExactnessOutcome run_exactness_study(const ExactnessOptions& o, const repro::RunContext& context,
                                     core::Progress* progress) {
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
  context.trials(
      jobs.size(),
      [&](std::size_t j) {
        const auto [f, t] = jobs[j];
        const ExactnessFamily& fam = o.families[f];
        core::Rng rng = context.streams().stream((static_cast<std::uint64_t>(f) << 20) + t);
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
        const PlanarProblem p = planar_problem(g);
        CertifyOptions certify = o.certify;
        certify.escalate = certify.escalate && fam.escalate;
        const CertifiedSolution c = solve_certified(g, p, certify);
        const MultistartMinimum ms = multistart_minimum(p, o.multistart_starts, o.multistart_refine, rng);
        ExactnessTrial& r = out.trials[f][t];
        r.upper = c.bound.upper;
        r.multistart = ms.cost;
        r.multistart_hits = ms.hits;
        r.best = std::min(r.upper, r.multistart);
        r.lower_order1 = c.first.lower_bound;
        r.lower_order2 = c.escalated ? c.second.lower_bound : 0.0;
        r.certified_order1 = c.certified_order == 1;
        r.certified = c.status == core::SearchStatus::optimal;
        r.escalated = c.escalated;
        r.escalation_skipped = !r.certified_order1 && !c.escalated;
        r.rank_ratio = c.first.rank_ratio;
        // The dual certificate at the best minimum. Its multipliers with the proven shift are a feasible
        // point of the order-1 SDP's dual (Q − diag(λ₀ − η, λ_i − η) ⪰ 0), so its bound Σλ − η · poses is a
        // second lower bound on order 1's value, independent of DSDP's iterates and, unlike DSDP's (λ_min(S)
        // from Eigen, no rounding margin), proven with one (linalg/psd_proof.hpp).
        const GlobalCertificate dual = certify_solution(p, r.multistart <= r.upper ? ms.z : c.z, o.dual);
        r.dual_certified = dual.certified();
        r.dual_gap = dual.relative_gap();
        r.lower_dual = dual.bound.lower;
        r.dual_failed_shift = dual.failed_shift;
        // Tightness of order 1 judged against the best minimum found, not against its own rounding, with the
        // better of the two bounds on its value (DSDP's numerical one, the dual certificate's proven one).
        const double lower = std::max(c.first.lower_bound, dual.bound.lower);
        r.gap_order1 = std::isfinite(lower) ? (r.best - lower) / std::max(r.best, 1.0)
                                            : std::numeric_limits<double>::infinity();
        r.tight_order1 = r.gap_order1 <= o.certify.gap_tolerance;
      },
      save, load, progress);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// The dual certificate of whole data sets

void GlobalCertificateStudyOptions::validate() const {
  lm.validate();
  if (!(random_extent > 0))
    throw std::invalid_argument(
        fmt::format("sos::GlobalCertificateStudyOptions.random_extent must be > 0 (got {})", random_extent));
  refine.validate();
  certificate.validate();
}

GlobalCertificateStudyOutcome run_global_certificate_study(
    const std::vector<GlobalCertificateDataset>& datasets, const GlobalCertificateStudyOptions& o,
    const repro::RunContext& context, core::Progress* progress) {
  o.validate();
  GlobalCertificateStudyOutcome out;
  for (std::size_t k = 0; k < datasets.size(); ++k) {
    const GlobalCertificateDataset& d = datasets[k];
    GlobalCertificateOutcome& r = out.datasets.emplace_back();
    r.name = d.name;
    r.poses = static_cast<int>(d.graph.poses.size());
    r.edges = static_cast<int>(d.graph.edges.size());
    r.landmarks = static_cast<int>(d.graph.landmarks.size());
    PlanarProblem p;
    try {
      p = planar_problem(d.graph);
    } catch (const std::invalid_argument& e) {
      r.failed = true;
      r.error = fmt::format("{} ({}): {}", d.name, d.file, e.what());
      if (progress) progress->advance(2);
      continue;
    }
    r.unknowns = p.unknowns();
    for (int which = 0; which < 2; ++which) {
      GlobalCertificateRun& run = which == 0 ? r.odometry : r.random;
      pgo::Options lm = o.lm;
      lm.constant_poses = {0};
      if (which == 0) {
        lm.initial_guess = pgo::InitialGuess::odometry;
      } else {
        lm.initial_guess = pgo::InitialGuess::random;
        lm.seed = context.streams().seed() + k;
        lm.random_extent = o.random_extent;
      }
      try {
        const auto ts = core::Clock::now();
        const pgo::Result2D res = pgo::optimize(d.graph, lm);
        run.solve_time_s = core::seconds_since(ts);
        run.lm_iterations = res.summary.iterations;
        Eigen::VectorXd z = unknowns_of(p, res.estimate.poses, res.estimate.landmarks);
        run.lm_cost = polynomial_cost(p, z);
        run.refine = refine_solution(p, z, o.refine);
        run.certificate = certify_solution(p, z, o.certificate);
      } catch (const std::exception& e) {
        run.failed = true;
        run.error = fmt::format("{}: {}", d.name, e.what());
      }
      if (progress) progress->advance();
    }
  }
  return out;
}

GlobalCertificateStudyOptions read_global_certificate_study_options(const core::ConfigTable& t) {
  GlobalCertificateStudyOptions o;
  o.lm.max_iterations = static_cast<int>(t.integer("lm_max_iterations"));
  o.random_extent = t.number("random_extent");
  o.refine.max_iterations = static_cast<int>(t.integer("refine_max_iterations"));
  o.refine.gradient_tolerance = t.number("refine_gradient_tolerance");
  o.certificate.stationarity_tolerance = t.number("stationarity_tolerance");
  o.certificate.gap_tolerance = t.number("gap_tolerance");
  o.certificate.bound_factorizations = static_cast<int>(t.integer("bound_factorizations"));
  t.validate(o);
  return o;
}

std::vector<std::pair<std::string, std::string>> read_global_certificate_files(const core::ConfigTable& t) {
  const core::ConfigTable files = t.table("graph_files");
  for (const std::string& key : files.keys()) (void)files.string(key);  // every entry must be a file name
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& name : t.strings("datasets")) {
    if (!files.has(name))
      throw core::ConfigError(
          fmt::format("{}: no graph_files.{} for data set '{}'", t.where("datasets"), name, name));
    out.emplace_back(name, files.string(name));
  }
  return out;
}

std::vector<GlobalCertificateDataset> load_global_certificate_datasets(
    const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<GlobalCertificateDataset> out;
  for (const auto& [name, file] : files) {
    GlobalCertificateDataset d;
    d.name = name;
    d.file = file;
    d.graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(name, d.file));
    out.push_back(std::move(d));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Config readers

CertifyOptions read_certify_options(const core::ConfigTable& t) {
  CertifyOptions o;
  o.relaxation.structure = t.parse("structure", sos::structure_from_string);
  o.relaxation.sdp.solver = t.parse("solver", convex::sdp_solver_from_string);
  o.relaxation.sdp.gap_tolerance = t.number("sdp_gap_tolerance");
  o.gap_tolerance = t.number("gap_tolerance");
  o.escalate = t.boolean("escalate");
  o.escalation_max_moments = static_cast<long>(t.integer("escalation_max_moments"));
  o.polish.max_iterations = static_cast<int>(t.integer("polish_max_iterations"));
  t.validate(o);
  return o;
}

SegmentStudyOptions read_segment_study_options(const core::ConfigTable& t) {
  SegmentStudyOptions o;
  o.segment_length = static_cast<int>(t.integer("segment_length"));
  o.stride = static_cast<int>(t.integer("stride"));
  o.max_segments = static_cast<int>(t.integer("max_segments"));
  o.random_extent = t.number("random_extent");
  o.lm.max_iterations = static_cast<int>(t.integer("lm_max_iterations"));
  o.sbsos = read_certify_options(t);
  t.validate(o);
  return o;
}

PlanarDatasetFiles PlanarDatasetFiles::read(const core::ConfigTable& t) {
  PlanarDatasetFiles f;
  f.name = t.string("dataset");
  f.graph_file = t.string("graph_file");
  f.ground_truth_file = t.string("ground_truth_file");
  f.ground_truth_key = t.where("ground_truth_file");
  if (t.has("ground_truth_landmarks_file"))
    f.ground_truth_landmarks_file = t.string("ground_truth_landmarks_file");
  return f;
}

PlanarDataset load_planar_dataset(const PlanarDatasetFiles& f) {
  PlanarDataset d;
  d.name = f.name;
  d.graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(d.name, f.graph_file));
  d.truth = graph::read_poses_2d(datasets::resolve_dataset_file(d.name, f.ground_truth_file));
  if (!f.ground_truth_landmarks_file.empty())
    d.truth_landmarks =
        graph::read_landmarks_2d(datasets::resolve_dataset_file(d.name, f.ground_truth_landmarks_file));
  if (d.truth.size() != d.graph.poses.size())
    throw core::ConfigError(fmt::format("{}: {} ground-truth poses for a graph of {} poses",
                                        f.ground_truth_key, d.truth.size(), d.graph.poses.size()));
  return d;
}

ExactnessOptions read_exactness_options(const core::ConfigTable& t, const std::string& families_table) {
  ExactnessOptions o;
  o.certify = read_certify_options(t);
  const core::ConfigTable fams = t.table(families_table);
  const int trials = static_cast<int>(t.integer("trials"));
  for (const std::string& name : t.strings("families")) {
    if (!fams.has(name))
      throw core::ConfigError(fmt::format("{}: no [{}.{}] table", t.where("families"), families_table, name));
    const core::ConfigTable f = fams.table(name);
    ExactnessFamily fam;
    fam.name = name;
    fam.poses = static_cast<int>(f.integer("poses"));
    fam.edge_probability = f.number("edge_probability");
    if (f.string_or("rotation_noise_kind", "normal") == "uniform") fam.uniform_rotations = true;
    fam.rotation_noise = f.number("rotation_noise");
    fam.translation_noise = f.number("translation_noise");
    fam.extent = f.number("extent");
    if (f.has("escalate")) fam.escalate = f.boolean("escalate");
    fam.trials = trials;
    o.families.push_back(fam);
  }
  if (t.has("noise_map")) {
    const core::ConfigTable m = t.table("noise_map");
    const std::vector<double> poses = m.numbers("poses"), noise = m.numbers("rotation_noise");
    const double edge_probability = m.number("edge_probability"),
                 translation_noise = m.number("translation_noise"), extent = m.number("extent");
    for (double n : poses)
      for (double sigma : noise) {
        ExactnessFamily fam;
        fam.poses = static_cast<int>(n);
        if (fam.poses != n || sigma < 0)
          throw core::ConfigError(fmt::format(
              "{}: poses must be integers and rotation_noise >= 0 (got {}, {})", m.where("poses"), n, sigma));
        fam.name = fmt::format("map_k{}_s{:04d}", fam.poses, static_cast<int>(std::lround(1000 * sigma)));
        fam.rotation_noise = sigma;
        fam.edge_probability = edge_probability, fam.translation_noise = translation_noise,
        fam.extent = extent;
        fam.trials = trials;
        fam.escalate = false;
        fam.noise_map = true;
        o.families.push_back(fam);
      }
  }
  o.multistart_starts = static_cast<int>(t.integer("multistart_starts"));
  o.multistart_refine.gradient_tolerance = t.number("multistart_gradient_tolerance");
  o.multistart_refine.max_iterations = static_cast<int>(t.integer("multistart_max_iterations"));
  o.dual.gap_tolerance = o.certify.gap_tolerance;
  o.dual.bound_factorizations = static_cast<int>(t.integer("dual_bound_factorizations"));
  t.validate(o);
  return o;
}

}  // namespace keel::study::ch4
