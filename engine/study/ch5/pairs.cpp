#include "study/ch5/pairs.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/timing.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "pgo/optimize.hpp"

namespace keel::study::ch5 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

namespace {

// Records what every pair study reports about the solve and the pairs.
void record_solved(Results& r, const SolvedPairs& s) {
  r.timing("read", s.read_time_s);
  r.timing("solve", s.solve_time_s);
  r.metric("solver.final_cost", s.final_cost);
  r.metric("solver.normalized_chi2", s.normalized_chi2);
  r.metric("solver.poses", static_cast<double>(s.poses.size()));
  r.metric("solver.edges", static_cast<double>(s.edges));
  r.timing("marginals", s.marginals_time_s);
  r.metric("pairs", static_cast<double>(s.pairs.size()));
}

// Records `<name>.mean` / `<name>.std` over all pairs and per offset (`offset<k>.<name>.mean`).
PairStatistics record_statistics(Results& r, const PairCorrelation::Outcome& s, double PairRecord::* field,
                                 const std::string& name) {
  const auto all = pair_statistics(s.records, field);
  r.metric(fmt::format("{}.mean", name), all.mean);
  r.metric(fmt::format("{}.std", name), all.std);
  for (int k : s.options.pairs.offsets) {
    const auto st = pair_statistics(s.records, field, k);
    r.metric(fmt::format("offset{}.{}.mean", k, name), st.mean);
    r.metric(fmt::format("offset{}.{}.std", k, name), st.std);
  }
  return all;
}

// One panel of Figs. 5.10–5.14: every pair at `offset` drawn as a segment between the two positions, coloured
// by `field` on [0, vmax] with `cmap`.
Panel pair_panel(const PairCorrelation::Outcome& s, int offset, double PairRecord::* field,
                 const std::string& title, const std::string& cmap, double vmax) {
  Panel panel;
  panel.title = title;
  panel.aspect = "equal";
  panel.colorbar = title;
  repro::Layer l;
  l.type = "segments";
  for (const auto& rec : s.records) {
    if (rec.j - rec.i != offset) continue;
    const auto& a = s.solved.poses[static_cast<std::size_t>(rec.i)].translation();
    const auto& b = s.solved.poses[static_cast<std::size_t>(rec.j)].translation();
    l.x0.push_back(a(0));
    l.y0.push_back(a(1));
    l.x1.push_back(b(0));
    l.y1.push_back(b(1));
    l.c.push_back(rec.*field);
  }
  l.cmap = cmap;
  l.vmin = 0.0;
  l.vmax = vmax > 0 ? vmax : 1.0;
  l.linewidth = 0.6;
  panel.layers.push_back(l);
  return panel;
}

// Least-squares line through (log x, log y): y = a·x^b. Returns {log a, b}.
std::pair<double, double> power_law(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double lx = std::log(x[k]), ly = std::log(y[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {(sy - b * sx) / n, b};
}

}  // namespace

PairsSetup PairsSetup::read(const core::ConfigTable& p) {
  PairsSetup s;
  s.dataset = p.string("dataset");
  s.file = p.string("file");
  s.initial_guess = p.parse("initial_guess", pgo::initial_guess_from_string);
  for (double k : p.numbers("offsets")) s.offsets.push_back(static_cast<int>(k));
  for (double k : p.numbers("figure_offsets")) s.figure_offsets.push_back(static_cast<int>(k));
  s.pair_stride = static_cast<int>(p.count("pair_stride"));
  s.offsets_key = p.where("offsets");
  return s;
}

SolvedPairs solve_pairs(const PairsSetup& setup, const RunContext& context) {
  pgo::Options options;
  options.initial_guess = setup.initial_guess;
  // One solver thread: Ceres sums cost and gradient per thread, so 1 and 2 threads differ in the last bits
  // and the result files would depend on the thread count. The solve takes well under a second either way.
  options.threads = 1;
  SolvedPairs out;
  auto t0 = core::Clock::now();
  const auto graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(setup.dataset, setup.file));
  out.read_time_s = core::seconds_since(t0);
  t0 = core::Clock::now();
  const auto solved = pgo::optimize(graph, options);
  out.solve_time_s = core::seconds_since(t0);
  const auto& sum = solved.summary;
  if (sum.termination != pgo::Termination::converged)
    throw std::runtime_error(fmt::format("the solver did not converge: {}", sum.message));
  out.final_cost = sum.final_cost;
  out.normalized_chi2 = sum.normalized_chi2;
  out.edges = graph.edges.size();
  out.poses = solved.estimate.poses;

  t0 = core::Clock::now();
  const auto info = cov::information_matrix(graph, out.poses);
  const cov::MarginalCovariance marginals(info);
  const int n = static_cast<int>(out.poses.size());
  for (int k : setup.offsets) {
    if (k < 1 || k >= n)
      throw core::ConfigError(fmt::format("{}: offset {} out of range", setup.offsets_key, k));
    for (int i = 0; i + k < n; i += setup.pair_stride) out.pairs.emplace_back(i, i + k);
  }
  out.covariances = cov::pair_marginals_2d(marginals, out.pairs, context.threads());
  out.marginals_time_s = core::seconds_since(t0);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Table 5.1

PairCorrelation::Options PairCorrelation::Options::read(const core::ConfigTable& p) {
  Options o;
  o.pairs = PairsSetup::read(p);
  o.simulation.samples = p.count("samples");
  return o;
}

PairCorrelation::Outcome PairCorrelation::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  out.solved = solve_pairs(o.pairs, context);
  const auto t0 = core::Clock::now();
  core::Progress progress = context.progress(out.solved.pairs.size());
  out.records = simulate_pairs_2d(out.solved.poses, out.solved.pairs, out.solved.covariances, o.simulation,
                                  context, &progress);
  progress.finish();
  out.monte_carlo_time_s = core::seconds_since(t0);
  return out;
}

void PairCorrelation::record(Results& r, const Outcome& s) {
  record_solved(r, s.solved);
  r.timing("monte_carlo", s.monte_carlo_time_s);
  const auto joint = record_statistics(r, s, &PairRecord::error_joint, "cov_error.joint");
  const auto ind = record_statistics(r, s, &PairRecord::error_independent, "cov_error.independent");

  std::size_t joint_lower = 0;
  for (const auto& rec : s.records) joint_lower += rec.error_joint < rec.error_independent ? 1 : 0;
  r.metric("cov_error.ratio", ind.mean / joint.mean);  // mean ε ignoring correlation / mean ε with it
  r.metric("joint_better_rate", static_cast<double>(joint_lower) /
                                    static_cast<double>(s.records.size()));  // pairs where joint ε is lower
  r.check("ignoring correlation raises the mean covariance error by more than two orders of magnitude",
          ind.mean > 100.0 * joint.mean,
          fmt::format("mean ε: joint {:.4g}, ignoring correlation {:.4g} (ratio {:.0f}; thesis 305)",
                      joint.mean, ind.mean, ind.mean / joint.mean));
  r.check("the joint prediction has the lower error for (almost) every pair (≥ 99 %)",
          joint_lower >= 0.99 * static_cast<double>(s.records.size()),
          fmt::format("{} of {} pairs", joint_lower, s.records.size()));
}

std::vector<Figure> PairCorrelation::figures(const Outcome& s) {
  std::vector<Figure> out;
  for (int k : s.options.pairs.figure_offsets) {
    const auto ik = pair_statistics(s.records, &PairRecord::error_independent, k);
    if (ik.count == 0) continue;
    const double vmax =
        ik.mean + 2.0 * ik.std;  // thesis: dark red = 2 std above the mean (correlation ignored)
    Figure f;
    f.file = fmt::format("_offset{}.png", k);
    f.title = fmt::format("Manhattan3500, pose pairs at offset {} (cf. Figs. 5.10–5.14 a–e)", k);
    f.rows = 2;
    f.cols = 3;
    f.width = 16.0;
    f.height = 10.0;
    f.panels.push_back(pair_panel(s, k, &PairRecord::corr_x, "(a) correlation x", "Greys", 1.0));
    f.panels.push_back(pair_panel(s, k, &PairRecord::corr_y, "(b) correlation y", "Greys", 1.0));
    f.panels.push_back(pair_panel(s, k, &PairRecord::corr_theta, "(c) correlation θ", "Greys", 1.0));
    f.panels.push_back(pair_panel(s, k, &PairRecord::error_joint, "(d) ε, joint", "Reds", vmax));
    f.panels.push_back(
        pair_panel(s, k, &PairRecord::error_independent, "(e) ε, correlation ignored", "Reds", vmax));
    out.push_back(std::move(f));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Table 5.2

void PairsVsSsc::record(Results& r, const Outcome& s) {
  record_solved(r, s.solved);
  r.timing("monte_carlo", s.monte_carlo_time_s);
  const auto lie_st = record_statistics(r, s, &PairRecord::normalized_error_lie, "norm_cov_error.lie");
  const auto ssc_st = record_statistics(r, s, &PairRecord::normalized_error_ssc, "norm_cov_error.ssc");
  (void)record_statistics(r, s, &PairRecord::normalized_error_ssc_raw_angles,
                          "norm_cov_error.ssc_raw_angles");
  const auto floor = record_statistics(r, s, &PairRecord::normalized_mc_floor, "norm_cov_error.mc_floor");
  r.check(
      "the proposed relative pose is within 1.5× of the Monte-Carlo sampling floor (first order is "
      "adequate)",
      lie_st.mean < 1.5 * floor.mean,
      fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g}, sampling floor {:.4g}", lie_st.mean,
                  ssc_st.mean, floor.mean));
  std::size_t lie_lower = 0;
  for (const auto& rec : s.records) lie_lower += rec.normalized_error_lie < rec.normalized_error_ssc ? 1 : 0;
  r.check("the proposed relative pose has a several-fold lower normalized covariance error than SSC (≥ 3×)",
          ssc_st.mean > 3.0 * lie_st.mean,
          fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g} (ratio {:.2f}; thesis 5.8)",
                      lie_st.mean, ssc_st.mean, ssc_st.mean / lie_st.mean));
  r.check("the proposed method is better than SSC for most pairs (> 50 %)", 2 * lie_lower > s.records.size(),
          fmt::format("{} of {} pairs", lie_lower, s.records.size()));
}

std::vector<Figure> PairsVsSsc::figures(const Outcome& s) {
  std::vector<Figure> out;
  for (int k : s.options.pairs.figure_offsets) {
    const auto sk = pair_statistics(s.records, &PairRecord::normalized_error_ssc, k);
    if (sk.count == 0) continue;
    const double vmax = sk.mean + 2.0 * sk.std;  // thesis: dark orange = 2 std above the mean (SSC)
    Figure f;
    f.file = fmt::format("_offset{}.png", k);
    f.title = fmt::format("Manhattan3500, pose pairs at offset {} (cf. Figs. 5.10–5.14 f–g)", k);
    f.width = 12.0;
    f.height = 5.5;
    f.panels.push_back(
        pair_panel(s, k, &PairRecord::normalized_error_lie, "(f) normalized ε, proposed", "Oranges", vmax));
    f.panels.push_back(
        pair_panel(s, k, &PairRecord::normalized_error_ssc, "(g) normalized ε, SSC", "Oranges", vmax));
    out.push_back(std::move(f));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Tables 5.1–5.2 against M

PairSampleSize::Options PairSampleSize::Options::read(const core::ConfigTable& p) {
  Options o;
  o.pairs = PairsSetup::read(p);
  o.samples = p.numbers("samples");
  o.match_cov_error_joint = p.number("match_cov_error_joint");
  o.match_norm_cov_error_lie = p.number("match_norm_cov_error_lie");
  if (o.samples.size() < 2)
    throw core::ConfigError(fmt::format("{}: need at least two sample sizes", p.where("samples")));
  return o;
}

PairSampleSize::Outcome PairSampleSize::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  out.rows = {
      {"cov_error.joint", "Table 5.1, joint", &PairRecord::error_joint, {}, {}},
      {"cov_error.independent", "Table 5.1, correlation ignored", &PairRecord::error_independent, {}, {}},
      {"norm_cov_error.lie", "Table 5.2, proposed", &PairRecord::normalized_error_lie, {}, {}},
      {"norm_cov_error.ssc", "Table 5.2, SSC", &PairRecord::normalized_error_ssc, {}, {}},
      {"norm_cov_error.mc_floor", "Table 5.2, sampling floor", &PairRecord::normalized_mc_floor, {}, {}}};
  out.solved = solve_pairs(o.pairs, context);
  core::Progress progress = context.progress(out.solved.pairs.size() * o.samples.size());
  for (double m : o.samples) {
    const auto t0 = core::Clock::now();
    PairStudySetup setup;
    setup.samples = static_cast<std::size_t>(m);
    // The same streams for every M: pair k draws from stream k.
    const auto records = simulate_pairs_2d(out.solved.poses, out.solved.pairs, out.solved.covariances, setup,
                                           context, &progress);
    out.monte_carlo_time_s.push_back(core::seconds_since(t0));
    for (auto& row : out.rows) {
      const auto st = pair_statistics(records, row.field);
      row.mean.push_back(st.mean), row.std.push_back(st.std);
    }
  }
  progress.finish();
  return out;
}

void PairSampleSize::record(Results& r, const Outcome& out) {
  const auto& ms = out.options.samples;
  record_solved(r, out.solved);
  for (std::size_t k = 0; k < ms.size(); ++k) {
    r.timing(fmt::format("monte_carlo.m{:g}", ms[k]), out.monte_carlo_time_s[k]);
    for (const auto& row : out.rows) {
      r.metric(fmt::format("m{:g}.{}.mean", ms[k], row.key), row.mean[k]);
      r.metric(fmt::format("m{:g}.{}.std", ms[k], row.key), row.std[k]);
    }
  }
  r.series("M", ms);
  for (const auto& row : out.rows) {
    r.series(row.key + ".mean", row.mean);
    r.series(row.key + ".std", row.std);
  }
  // The power laws of the two errors the thesis's means are compared with, and the M at which each fit meets
  // the thesis's mean (extrapolated when outside the sweep).
  auto fit = [&](const Row& row, double target, const std::string& name) {
    const auto [log_a, b] = power_law(ms, row.mean);
    r.metric(name + ".exponent", b);
    r.metric(name + ".m_at_thesis", std::exp((std::log(target) - log_a) / b));
    return std::pair{log_a, b};
  };
  const auto fj = fit(out.rows[0], out.options.match_cov_error_joint, "cov_error.joint");
  const auto fl = fit(out.rows[2], out.options.match_norm_cov_error_lie, "norm_cov_error.lie");
  r.check("the joint error falls with M (a Monte-Carlo-limited metric): fitted exponent below zero",
          fj.second < 0, fmt::format("mean ε ∝ M^{:.3f}", fj.second));
  r.check("the proposed method's normalized error falls with M: fitted exponent below zero", fl.second < 0,
          fmt::format("mean normalized ε ∝ M^{:.3f}", fl.second));
}

std::vector<Figure> PairSampleSize::figures(const Outcome& out) {
  const auto& ms = out.options.samples;
  const auto& rows = out.rows;
  Figure f;
  f.file = ".png";
  f.title = "Tables 5.1–5.2: mean covariance errors against the Monte-Carlo sample size M";
  f.width = 13.0;
  f.height = 5.5;
  Panel a, b;
  a.title = "Table 5.1: ε (eq. 5.56)";
  b.title = "Table 5.2: normalized ε";
  for (auto* p : {&a, &b}) {
    p->xlabel = "Monte-Carlo samples per pair M";
    p->ylabel = "mean over pairs";
    p->xscale = p->yscale = "log";
  }
  a.layers.push_back(repro::line_layer(ms, rows[0].mean, "joint (ours)", "tab:green", "o"));
  a.layers.push_back(repro::line_layer(ms, rows[1].mean, "correlation ignored (ours)", "tab:red", "s"));
  a.layers.push_back(repro::hline_layer(out.options.match_cov_error_joint, "thesis, joint", "tab:green"));
  b.layers.push_back(repro::line_layer(ms, rows[2].mean, "proposed (ours)", "tab:green", "o"));
  b.layers.push_back(repro::line_layer(ms, rows[3].mean, "SSC (ours)", "tab:red", "s"));
  b.layers.push_back(repro::line_layer(ms, rows[4].mean, "sampling floor", "0.4", "x"));
  b.layers.push_back(
      repro::hline_layer(out.options.match_norm_cov_error_lie, "thesis, proposed", "tab:green"));
  f.panels = {a, b};
  return {f};
}

}  // namespace keel::study::ch5
