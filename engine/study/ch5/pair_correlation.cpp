#include "study/ch5/pair_correlation.hpp"

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

PairStatistics record_statistics(Results& r, const PairCorrelation::Outcome& s, double PairRecord::* field,
                                 const repro::KeyPath& name) {
  const auto all = pair_statistics(s.records, field);
  r.at(name).metric("mean", all.mean);
  r.at(name).metric("std", all.std);
  for (int k : s.options.pairs.offsets) {
    const auto st = pair_statistics(s.records, field, k);
    const auto at = r.under(fmt::format("offset{}", k)).under(name);
    at.metric("mean", st.mean);
    at.metric("std", st.std);
  }
  return all;
}

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
  const auto joint =
      record_statistics(r, s, &PairRecord::error_joint, repro::path("cov_error").under("joint"));
  const auto ind =
      record_statistics(r, s, &PairRecord::error_independent, repro::path("cov_error").under("independent"));

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

}  // namespace keel::study::ch5
