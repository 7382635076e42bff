#include "study/ch2/world1d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/names.hpp"
#include "core/parallel.hpp"
#include "core/timing.hpp"
#include "pcm/clique.hpp"

namespace keel::study::ch2 {

using namespace keel::pcm;  // consistency matrices and the selection methods
using namespace keel::sim;  // the 1D world

namespace {

using core::Clock;
using core::seconds_since;

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// Monte-Carlo study

namespace {
constexpr core::NameTable<Selector1D, 5> kSelector1DNames{"ch2::Selector1D",
                                                          {{{Selector1D::combinatorial, "combinatorial"},
                                                            {Selector1D::pcm_exact, "pcm_exact"},
                                                            {Selector1D::pcm_heuristic, "pcm_heuristic"},
                                                            {Selector1D::scgp, "scgp"},
                                                            {Selector1D::ransac, "ransac"}}}};
}  // namespace

std::string_view to_string(Selector1D v) { return kSelector1DNames.name(v); }
Selector1D selector1d_from_string(std::string_view s) { return kSelector1DNames.parse(s); }

void World1DStudyOptions::validate() const {
  world.validate();
  validate_gamma(pcm_gamma, "World1DStudyOptions::pcm_gamma");
  validate_gamma(ransac_gamma, "World1DStudyOptions::ransac_gamma");
  scgp.validate();
  if (worlds < 1) throw std::invalid_argument("World1DStudyOptions::worlds must be >= 1");
  if (selectors.empty()) throw std::invalid_argument("World1DStudyOptions::selectors is empty");
  for (std::size_t i = 0; i < selectors.size(); ++i)
    for (std::size_t j = i + 1; j < selectors.size(); ++j)
      if (selectors[i] == selectors[j])
        throw std::invalid_argument(
            fmt::format("World1DStudyOptions::selectors lists '{}' twice", to_string(selectors[i])));
  const bool comb =
      std::find(selectors.begin(), selectors.end(), Selector1D::combinatorial) != selectors.end();
  const int max_m = world.inliers_max + world.aliased_max + world.random_max;
  const int limit = combinatorial == CombinatorialMethod::exhaustive ? kCombinatorialExhaustiveMax
                                                                     : kCombinatorialPrunedMax;
  if (comb && max_m > limit) {
    throw std::invalid_argument(fmt::format(
        "World1DStudyOptions: worlds of up to {} measurements exceed the {} combinatorial limit of {}", max_m,
        to_string(combinatorial), limit));
  }
}

const std::vector<World1DOutcome>& World1DStudy::of(Selector1D s) const {
  for (std::size_t k = 0; k < selectors.size(); ++k)
    if (selectors[k] == s) return outcome[k];
  throw std::invalid_argument(fmt::format("World1DStudy: selector '{}' was not run", to_string(s)));
}

World1DStudy run_world1d_study(const World1DStudyOptions& options, const repro::RunContext& context,
                               core::Progress* progress) {
  options.validate();
  const std::size_t n = options.worlds, k = options.selectors.size();
  World1DStudy study;
  study.selectors = options.selectors;
  study.measurements.assign(n, 0);
  study.inliers.assign(n, 0);
  study.outcome.assign(k, std::vector<World1DOutcome>(n));
  // A trial is one world: its counts and every selector's outcome (the record a shard saves).
  const auto save = [&](repro::Writer& w, std::size_t i) {
    repro::save(w, study.measurements[i]);
    repro::save(w, study.inliers[i]);
    for (std::size_t s = 0; s < k; ++s) repro::save(w, study.outcome[s][i]);
  };
  const auto load = [&](repro::Reader& r, std::size_t i) {
    repro::load(r, study.measurements[i]);
    repro::load(r, study.inliers[i]);
    for (std::size_t s = 0; s < k; ++s) repro::load(r, study.outcome[s][i]);
  };
  context.trials(
      n,
      [&](std::size_t i) {
        const World1D w =
            generate_world1d(options.world, context.streams().seed(), context.streams().index(i));
        const ConsistencyMatrix Q = world1d_consistency_matrix(w);  // shared by every method, not timed
        study.measurements[i] = w.size();
        study.inliers[i] = w.count(MeasurementLabel::inlier);
        for (std::size_t s = 0; s < k; ++s) {
          std::vector<int> selected;
          double t = 0.0;
          switch (options.selectors[s]) {
            case Selector1D::combinatorial: {
              auto r = max_consistent_set_combinatorial(Q, options.pcm_gamma, options.combinatorial);
              selected = std::move(r.selected);
              t = r.time_s;
              break;
            }
            case Selector1D::pcm_exact:
            case Selector1D::pcm_heuristic: {
              const auto algo = options.selectors[s] == Selector1D::pcm_exact ? CliqueAlgorithm::exact
                                                                              : CliqueAlgorithm::heuristic;
              auto r = select_pcm(Q, options.pcm_gamma, algo);
              selected = std::move(r.selected);
              t = r.time_s;
              break;
            }
            case Selector1D::scgp: {
              auto r = select_scgp(Q, options.scgp);
              selected = std::move(r.selected);
              t = r.time_s;
              break;
            }
            case Selector1D::ransac: {
              auto r = select_ransac(Q, options.ransac_gamma);
              selected = std::move(r.selected);
              t = r.time_s;
              break;
            }
          }
          World1DOutcome& o = study.outcome[s][i];
          o.size = static_cast<int>(selected.size());
          o.inconsistent_pairs = count_inconsistent_pairs(Q, selected, options.pcm_gamma);
          for (int u : selected) o.inliers += w.labels[u] == MeasurementLabel::inlier;
          o.time_s = t;
        }
      },
      save, load, progress);
  return study;
}

CombinatorialComparison compare_to_combinatorial(const World1DStudy& study,
                                                 const std::vector<Selector1D>& selectors) {
  const auto& comb = study.of(Selector1D::combinatorial);
  const std::size_t n = comb.size();
  CombinatorialComparison out;
  // Histogram ranges shared by all selectors (size difference to the maximum; inconsistent pairs).
  int dmin = 0, dmax = 0, imax = 0;
  for (auto m : selectors) {
    const auto& o = study.of(m);
    for (std::size_t i = 0; i < n; ++i) {
      dmin = std::min(dmin, o[i].size - comb[i].size);
      dmax = std::max(dmax, o[i].size - comb[i].size);
      imax = std::max(imax, o[i].inconsistent_pairs);
    }
  }
  for (int d = dmin; d <= dmax; ++d) out.size_diff_bins.push_back(d);
  for (int k = 0; k <= imax; ++k) out.inconsistent_bins.push_back(k);
  const double worlds = static_cast<double>(n);
  for (auto m : selectors) {
    const auto& o = study.of(m);
    SelectorComparison row;
    row.selector = m;
    row.size_diff_hist.assign(out.size_diff_bins.size(), 0.0);
    row.inconsistent_hist.assign(out.inconsistent_bins.size(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const int d = o[i].size - comb[i].size;
      row.match_rate += d == 0;
      row.larger_rate += d > 0;
      row.smaller_rate += d < 0;
      row.inconsistent_total += o[i].inconsistent_pairs;
      row.inconsistent_rate += o[i].inconsistent_pairs > 0;
      row.time_mean_s += o[i].time_s;
      row.size_diff_hist[static_cast<std::size_t>(d - dmin)] += 1.0;
      row.inconsistent_hist[static_cast<std::size_t>(o[i].inconsistent_pairs)] += 1.0;
    }
    for (auto& c : row.size_diff_hist) c /= worlds;  // fractions of worlds
    for (auto& c : row.inconsistent_hist) c /= worlds;
    row.match_rate /= worlds;
    row.larger_rate /= worlds;
    row.smaller_rate /= worlds;
    row.inconsistent_mean = static_cast<double>(row.inconsistent_total) / worlds;
    row.inconsistent_rate /= worlds;
    row.time_mean_s /= worlds;
    out.rows.push_back(std::move(row));
  }
  const auto ran = [&](Selector1D s) {
    return std::find(study.selectors.begin(), study.selectors.end(), s) != study.selectors.end();
  };
  if (ran(Selector1D::pcm_exact) && ran(Selector1D::pcm_heuristic)) {
    const auto &exact = study.of(Selector1D::pcm_exact), &heur = study.of(Selector1D::pcm_heuristic);
    for (std::size_t i = 0; i < n; ++i) out.heuristic_above_exact += heur[i].size > exact[i].size;
  }
  return out;
}

void TimingSweepOptions::validate() const {
  if (sizes.empty()) throw std::invalid_argument("TimingSweepOptions::sizes must not be empty");
  for (std::size_t k = 0; k < sizes.size(); ++k)
    if (sizes[k] < 1 || (k > 0 && sizes[k] <= sizes[k - 1]))
      throw std::invalid_argument("TimingSweepOptions::sizes must be positive integers in increasing order");
  if (exhaustive_max < 1 || exhaustive_max > kCombinatorialExhaustiveMax)
    throw std::invalid_argument(fmt::format("TimingSweepOptions::exhaustive_max must be in [1, {}] (got {})",
                                            kCombinatorialExhaustiveMax, exhaustive_max));
  if (pruned_max < 1 || pruned_max > kCombinatorialPrunedMax)
    throw std::invalid_argument(fmt::format("TimingSweepOptions::pruned_max must be in [1, {}] (got {})",
                                            kCombinatorialPrunedMax, pruned_max));
}

std::size_t TimingSweepOptions::work() const {
  std::size_t total = 0;
  for (int m : sizes) total += base.worlds * (1 + (m <= pruned_max ? 1 : 0));
  return total;
}

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

TimingSweep run_timing_sweep(const TimingSweepOptions& options, const repro::RunContext& context,
                             core::Progress* progress) {
  options.validate();
  using S = Selector1D;
  struct Curve {
    const char* name;
    S selector;
    int max_m;  // 0: no cap
  };
  const Curve curves[] = {{"combinatorial_exhaustive", S::combinatorial, options.exhaustive_max},
                          {"combinatorial_pruned", S::combinatorial, options.pruned_max},
                          {"pcm_exact", S::pcm_exact, 0},
                          {"pcm_heuristic", S::pcm_heuristic, 0},
                          {"scgp", S::scgp, 0},
                          {"ransac", S::ransac, 0}};
  const auto runs_at = [](const Curve& c, int m) { return c.max_m == 0 || m <= c.max_m; };
  TimingSweep out;
  for (const auto& c : curves) out.curves.push_back({c.name, {}, {}, {}});
  for (std::size_t k = 0; k < options.sizes.size(); ++k) {
    const int m = options.sizes[k];
    World1DStudyOptions o = options.base;
    o.world =
        world1d_options_with_total(options.base.world, m, options.inlier_fraction, options.aliased_fraction);
    // Independent worlds per size, the same for every curve.
    const repro::RunContext size_context =
        context.with_streams(context.streams().offset(static_cast<std::uint64_t>(k) << 32));
    o.selectors = {S::pcm_exact, S::pcm_heuristic, S::scgp, S::ransac};
    o.combinatorial = CombinatorialMethod::exhaustive;
    if (runs_at(curves[0], m)) o.selectors.push_back(S::combinatorial);
    const World1DStudy main = run_world1d_study(o, size_context, progress);
    World1DStudy pruned;
    if (runs_at(curves[1], m)) {
      o.selectors = {S::combinatorial};
      o.combinatorial = CombinatorialMethod::pruned;
      pruned = run_world1d_study(o, size_context, progress);
    }
    const auto& exact = main.of(S::pcm_exact);
    for (std::size_t c = 0; c < std::size(curves); ++c) {
      if (!runs_at(curves[c], m)) continue;
      const auto& res = (c == 1 ? pruned : main).of(curves[c].selector);
      std::vector<double> t;
      double n_sel = 0;
      for (std::size_t i = 0; i < res.size(); ++i) {
        t.push_back(res[i].time_s);
        n_sel += res[i].size;
        if (curves[c].selector == S::combinatorial) {
          ++out.combinatorial_checked;
          out.combinatorial_mismatch += res[i].size != exact[i].size;
        }
      }
      auto& curve = out.curves[c];
      curve.m.push_back(m);
      curve.median_time_s.push_back(median(t));
      curve.size_mean.push_back(n_sel / res.size());
    }
    const auto& heur = main.of(S::pcm_heuristic);
    double match = 0;
    for (std::size_t i = 0; i < exact.size(); ++i) match += heur[i].size == exact[i].size;
    out.heuristic_match.push_back(match / exact.size());
  }
  return out;
}

}  // namespace keel::study::ch2
