#include "study/ch2/clique_scale.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <stdexcept>

#include "core/names.hpp"
#include "repro/results.hpp"
#include "core/random.hpp"
#include "core/timing.hpp"
#include "lie/se2.hpp"
#include "pcm/consistency.hpp"
#include "pcm/selection.hpp"
#include "sim/random_graph.hpp"
#include "sim/two_robot.hpp"
#include "sim/world1d.hpp"

namespace keel::study::ch2 {

namespace {

constexpr core::NameTable<CliqueScaleMethod, kCliqueScaleMethods> kCliqueScaleMethodNames{
    "ch2::CliqueScaleMethod",
    {{{CliqueScaleMethod::exact, "exact"},
      {CliqueScaleMethod::heuristic, "heuristic"},
      {CliqueScaleMethod::densest, "densest"}}}};

int count_hits(const std::vector<int>& selected, const std::vector<char>& in_reference) {
  int hits = 0;
  for (int v : selected) hits += in_reference[static_cast<std::size_t>(v)] != 0;
  return hits;
}

}  // namespace

std::string_view to_string(CliqueScaleMethod m) { return kCliqueScaleMethodNames.name(m); }
CliqueScaleMethod clique_scale_method_from_string(std::string_view s) {
  return kCliqueScaleMethodNames.parse(s);
}

int first_moment_clique_number(int n, double p) {
  if (n < 1) throw std::invalid_argument(fmt::format("first_moment_clique_number: n = {} must be >= 1", n));
  if (!(p >= 0.0 && p <= 1.0))
    throw std::invalid_argument(fmt::format("first_moment_clique_number: p = {} not in [0, 1]", p));
  if (p == 1.0) return n;
  if (p == 0.0) return 1;
  // log E[#k-cliques] = log C(n, k) + k(k−1)/2 · log p is >= 0 at k = 1 (= log n) and concave in k (the ratio
  // E_{k+1} / E_k = (n − k) / (k + 1) · p^k decreases), so the scan stops at its first negative value.
  const double lp = std::log(p), lgn = std::lgamma(n + 1.0);
  int best = 1;
  for (int k = 2; k <= n; ++k) {
    const double lc = lgn - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0);
    const double le = lc + 0.5 * k * (k - 1.0) * lp;
    if (le < -1e-12) break;
    best = k;
  }
  return best;
}

void CliqueScaleOptions::validate() const {
  if (exact_node_limit < 1)
    throw std::invalid_argument(
        fmt::format("CliqueScaleOptions::exact_node_limit = {} must be >= 1", exact_node_limit));
  if (reference_max_vertices < 0)
    throw std::invalid_argument(
        fmt::format("CliqueScaleOptions::reference_max_vertices = {} must be >= 0", reference_max_vertices));
  densest.validate();
}

long long non_adjacent_pairs(const pcm::ConsistencyGraph& g, const std::vector<int>& vertices) {
  long long bad = 0;
  for (std::size_t a = 0; a < vertices.size(); ++a)
    for (std::size_t b = a + 1; b < vertices.size(); ++b) bad += !g.adjacent(vertices[a], vertices[b]);
  return bad;
}

CliqueGraphOutcome compare_clique_methods(const pcm::ConsistencyGraph& g, const std::vector<int>& reference,
                                          const CliqueScaleOptions& options) {
  options.validate();
  std::vector<char> in_reference(static_cast<std::size_t>(g.size()), 0);
  for (int v : reference) {
    if (v < 0 || v >= g.size())
      throw std::invalid_argument(
          fmt::format("compare_clique_methods: reference vertex {} outside [0, {})", v, g.size()));
    if (in_reference[static_cast<std::size_t>(v)] != 0)
      throw std::invalid_argument(fmt::format("compare_clique_methods: reference vertex {} repeated", v));
    in_reference[static_cast<std::size_t>(v)] = 1;
  }
  CliqueGraphOutcome out;
  out.vertices = g.size();
  out.edges = g.num_edges();
  out.reference = static_cast<int>(reference.size());
  const auto from_search = [&](const pcm::CliqueResult& r) {
    CliqueMethodOutcome o;
    o.size = static_cast<int>(r.clique.size());
    o.hits = count_hits(r.clique, in_reference);
    o.violations = non_adjacent_pairs(g, r.clique);
    o.raw_size = o.size;
    o.raw_violations = o.violations;
    o.upper_bound = r.upper_bound;
    o.status = r.status;
    o.nodes = r.nodes_explored;
    o.time_s = r.time_s;
    return o;
  };
  pcm::CliqueOptions exact;
  exact.node_limit = options.exact_node_limit;
  out.methods[static_cast<std::size_t>(CliqueScaleMethod::exact)] =
      from_search(pcm::maximum_clique_exact(g, exact));
  out.methods[static_cast<std::size_t>(CliqueScaleMethod::heuristic)] =
      from_search(pcm::maximum_clique_heuristic(g));
  if (g.size() <= options.reference_max_vertices) {
    pcm::CliqueOptions plain;
    plain.recolour = false;
    plain.maxsat_bound = false;
    out.reference_size = static_cast<int>(pcm::maximum_clique_exact(g, plain).clique.size());
  }
  const auto d = pcm::densest_subgraph(g, options.densest);
  CliqueMethodOutcome& o = out.methods[static_cast<std::size_t>(CliqueScaleMethod::densest)];
  o.size = static_cast<int>(d.selection.size());
  o.hits = count_hits(d.selection, in_reference);
  o.violations = non_adjacent_pairs(g, d.selection);
  o.raw_size = static_cast<int>(d.raw.size());
  o.raw_violations = non_adjacent_pairs(g, d.raw);  // recounted from the graph, not taken from the solver
  o.time_s = d.time_s;
  return out;
}

CliqueMethodSummary summarize_clique_method(const std::vector<CliqueGraphOutcome>& outcomes,
                                            std::size_t first, std::size_t last, CliqueScaleMethod method) {
  if (first >= last || last > outcomes.size())
    throw std::invalid_argument(
        fmt::format("summarize_clique_method: span [{}, {}) of {} outcomes", first, last, outcomes.size()));
  CliqueMethodSummary s;
  s.graphs = last - first;
  s.size_min = outcomes[first].of(method).size;
  s.size_max = s.size_min;
  long long hits = 0, size = 0, reference = 0;
  double raw_size = 0, raw_violations = 0, upper = 0, gap = 0, nodes = 0, time = 0;
  for (std::size_t i = first; i < last; ++i) {
    const auto& o = outcomes[i].of(method);
    hits += o.hits;
    size += o.size;
    reference += outcomes[i].reference;
    s.size_min = std::min(s.size_min, o.size);
    s.size_max = std::max(s.size_max, o.size);
    raw_size += o.raw_size;
    raw_violations += static_cast<double>(o.raw_violations);
    s.raw_violating_graphs += o.raw_violations > 0;
    s.violations_total += o.violations;
    s.optimal_graphs += o.status == pcm::SearchStatus::optimal;
    if (method != CliqueScaleMethod::densest) {
      upper += o.upper_bound;
      gap += o.upper_bound - o.size;
      s.gap_max = std::max(s.gap_max, o.upper_bound - o.size);
    }
    nodes += static_cast<double>(o.nodes);
    time += o.time_s;
    s.time_max_s = std::max(s.time_max_s, o.time_s);
  }
  const double g = static_cast<double>(s.graphs);
  s.size_mean = static_cast<double>(size) / g;
  s.precision = size > 0 ? static_cast<double>(hits) / static_cast<double>(size) : 0.0;
  s.recall = reference > 0 ? static_cast<double>(hits) / static_cast<double>(reference) : 0.0;
  s.raw_size_mean = raw_size / g;
  s.raw_violations_mean = raw_violations / g;
  s.upper_bound_mean = upper / g;
  s.gap_mean = gap / g;
  s.nodes_mean = nodes / g;
  s.time_mean_s = time / g;
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// Planted cliques

void PlantedCliqueStudyOptions::validate() const {
  if (sizes.empty()) throw std::invalid_argument("PlantedCliqueStudyOptions::sizes is empty");
  if (clique_fractions.empty())
    throw std::invalid_argument("PlantedCliqueStudyOptions::clique_fractions is empty");
  if (densities.empty()) throw std::invalid_argument("PlantedCliqueStudyOptions::densities is empty");
  for (int n : sizes)
    if (n < 2)
      throw std::invalid_argument(fmt::format("PlantedCliqueStudyOptions::sizes: {} must be >= 2", n));
  for (double f : clique_fractions)
    if (!(f > 0.0 && f <= 1.0))
      throw std::invalid_argument(
          fmt::format("PlantedCliqueStudyOptions::clique_fractions: {} not in (0, 1]", f));
  for (double p : densities)
    if (!(p >= 0.0 && p <= 1.0))
      throw std::invalid_argument(fmt::format("PlantedCliqueStudyOptions::densities: {} not in [0, 1]", p));
  if (clique_min < 1)
    throw std::invalid_argument(
        fmt::format("PlantedCliqueStudyOptions::clique_min = {} must be >= 1", clique_min));
  for (int n : sizes)
    if (clique_min > n)
      throw std::invalid_argument(
          fmt::format("PlantedCliqueStudyOptions::clique_min = {} exceeds n = {}", clique_min, n));
  if (seeds < 1) throw std::invalid_argument("PlantedCliqueStudyOptions::seeds must be >= 1");
  methods.validate();
}

std::vector<PlantedCliqueCell> PlantedCliqueStudyOptions::cells() const {
  validate();
  std::vector<PlantedCliqueCell> out;
  for (int n : sizes) {
    std::vector<int> ks;
    for (double f : clique_fractions) {
      const int k = std::min(n, std::max(clique_min, static_cast<int>(std::lround(f * n))));
      if (std::find(ks.begin(), ks.end(), k) != ks.end()) continue;
      ks.push_back(k);
      for (double p : densities) out.push_back({n, k, p, first_moment_clique_number(n, p)});
    }
  }
  return out;
}

PlantedCliqueStudy run_planted_clique_study(const PlantedCliqueStudyOptions& options,
                                            const repro::RunContext& context, core::Progress* progress) {
  PlantedCliqueStudy study;
  study.cells = options.cells();
  study.seeds = options.seeds;
  const std::size_t total = study.cells.size() * options.seeds;
  study.outcomes.assign(total, {});
  context.trials(
      total,
      [&](std::size_t t) {
        const std::size_t c = t / options.seeds, s = t % options.seeds;
        const auto& cell = study.cells[c];
        const std::uint64_t graph_seed = context.streams().stream(c << 32 | s).next();
        const auto planted = sim::planted_clique_graph(cell.n, cell.k, cell.p, graph_seed);
        study.outcomes[t] = compare_clique_methods(planted.graph, planted.planted, options.methods);
      },
      progress, study.outcomes);
  return study;
}

// ---------------------------------------------------------------------------------------------------------------
// 1D worlds

void World1DCliqueOptions::validate() const {
  world.validate();
  pcm::validate_gamma(gamma, "World1DCliqueOptions::gamma");
  if (worlds < 1) throw std::invalid_argument("World1DCliqueOptions::worlds must be >= 1");
  methods.validate();
}

std::vector<CliqueGraphOutcome> run_world1d_clique_study(const World1DCliqueOptions& options,
                                                         const repro::RunContext& context,
                                                         core::Progress* progress) {
  options.validate();
  std::vector<CliqueGraphOutcome> out(options.worlds);
  context.trials(
      options.worlds,
      [&](std::size_t i) {
        const auto w =
            sim::generate_world1d(options.world, context.streams().seed(), context.streams().index(i));
        const auto Q = sim::world1d_consistency_matrix(w);
        const auto g = pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, options.gamma);
        std::vector<int> inliers;
        for (int u = 0; u < w.size(); ++u)
          if (w.labels[static_cast<std::size_t>(u)] == sim::MeasurementLabel::inlier) inliers.push_back(u);
        out[i] = compare_clique_methods(g, inliers, options.methods);
      },
      progress, out);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Two-robot data sets

std::vector<CliqueGraphOutcome> run_two_robot_clique_study(const sim::TwoRobotScenario2& scenario,
                                                           const LocalPair<lie::SE2>& local,
                                                           const sim::CandidateOptions& candidates, double p,
                                                           pcm::Composition composition,
                                                           const CliqueScaleOptions& options,
                                                           const repro::RunContext& context,
                                                           std::size_t count, core::Progress* progress) {
  options.validate();
  if (count < 1) throw std::invalid_argument("run_two_robot_clique_study: count must be >= 1");
  (void)pcm::consistency_threshold(p, lie::SE2::DoF);  // validates p
  std::vector<CliqueGraphOutcome> out(count);
  context.trials(
      count,
      [&](std::size_t i) {
        const auto set = sim::generate_candidates(scenario, candidates, context.streams().seed(),
                                                  context.streams().index(i));
        const auto maps = local_maps(local.a, local.b, set.candidates);
        pcm::ConsistencyOptions co;
        co.composition = composition;
        co.threads = 1;
        const auto Q = pcm::consistency_matrix(maps.a, maps.b, set.candidates, co);
        const auto g = pcm::ConsistencyGraph::from_threshold(Q.n, Q.q, pcm::consistency_threshold(p, Q.dof));
        out[i] = compare_clique_methods(g, set.inliers(), options);
      },
      progress, out);
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Recording

void CliqueScaleTally::add(const std::vector<CliqueGraphOutcome>& outcomes, std::size_t first,
                           std::size_t last, int planted_k) {
  for (std::size_t i = first; i < last; ++i) {
    const auto& g = outcomes[i];
    const auto& ex = g.of(CliqueScaleMethod::exact);
    ++graphs;
    exact_below_heuristic += ex.size < g.of(CliqueScaleMethod::heuristic).size;
    if (g.reference_size >= 0) {
      ++reference_checked;
      reference_mismatch += ex.status != pcm::SearchStatus::optimal || ex.size != g.reference_size;
    }
    densest_raw_violating += g.of(CliqueScaleMethod::densest).raw_violations > 0;
    for (const auto& o : g.methods) {
      not_cliques += o.violations > 0;
      above_bound += o.size > ex.upper_bound;
    }
    if (ex.status == pcm::SearchStatus::optimal) {
      ++optimal;
      optimal_inconsistent += ex.size != ex.upper_bound;
      below_planted += planted_k > 0 && ex.size < planted_k;
    }
  }
}

void CliqueScaleTally::record(repro::Results& r, int reference_max_vertices) const {
  r.metric("all.graphs", static_cast<double>(graphs));
  r.metric("all.exact.optimal_graphs", static_cast<double>(optimal));
  r.metric("all.densest.raw_violating_graphs", static_cast<double>(densest_raw_violating));
  r.metric("all.reference_graphs", static_cast<double>(reference_checked));
  r.check("the exact search never returns a smaller clique than the heuristic", exact_below_heuristic == 0,
          fmt::format("{} of {} graphs", exact_below_heuristic, graphs));
  r.check(
      "every method's output is a clique (the densest subgraph after its repair)", not_cliques == 0,
      fmt::format("{} outputs with a non-adjacent pair, of {}", not_cliques, kCliqueScaleMethods * graphs));
  r.check(
      fmt::format("on graphs of at most {} vertices the exact search proves optimal the size that the "
                  "colouring-only exact search finds",
                  reference_max_vertices),
      reference_checked > 0 && reference_mismatch == 0,
      fmt::format("{} graphs compared, {} differ or are not proven", reference_checked, reference_mismatch));
  r.check("no method returns a clique larger than the exact search's proven upper bound", above_bound == 0,
          fmt::format("{} outputs above the bound", above_bound));
  r.check(
      "where the exact search proves optimality, its clique has the bound's size and at least the planted "
      "k",
      optimal_inconsistent == 0 && below_planted == 0,
      fmt::format("{} proven optimal of {} graphs; {} with size != bound, {} below the planted k", optimal,
                  graphs, optimal_inconsistent, below_planted));
}

void record_clique_group(repro::Results& r, const repro::KeyPath& prefix,
                         const std::vector<CliqueGraphOutcome>& outcomes, std::size_t first, std::size_t last,
                         int planted_k, CliqueScaleTally& tally) {
  for (auto m : kAllCliqueScaleMethods) {
    const auto s = summarize_clique_method(outcomes, first, last, m);
    const auto n = r.at(prefix.under(to_string(m)));
    n.metric("size", s.size_mean);
    n.metric("size_min", s.size_min);
    n.metric("precision", s.precision);
    n.metric("recall", s.recall);
    n.metric("violations", static_cast<double>(s.violations_total));  // in the outputs (0: cliques)
    if (m == CliqueScaleMethod::densest) {
      n.metric("raw_size", s.raw_size_mean);
      n.metric("raw_violations", s.raw_violations_mean);
      n.metric("raw_violating_graphs", static_cast<double>(s.raw_violating_graphs));
    }
    if (m == CliqueScaleMethod::exact) {
      n.metric("optimal", static_cast<double>(s.optimal_graphs) / static_cast<double>(s.graphs));
      n.metric("upper_bound", s.upper_bound_mean);
      n.metric("gap", s.gap_mean);
      n.metric("gap_max", s.gap_max);
      n.metric("nodes", s.nodes_mean);
    }
    n.timing("time_s", s.time_mean_s);
    n.timing("time_s.max", s.time_max_s);
  }
  tally.add(outcomes, first, last, planted_k);
}

repro::KeyPath planted_cell_path(const PlantedCliqueCell& cell) {
  return repro::path("planted")
      .under(fmt::format("n{:04d}", cell.n))
      .under(fmt::format("k{:04d}", cell.k))
      .under(fmt::format("p{:02d}", static_cast<int>(std::lround(100 * cell.p))));
}

void record_planted_clique_study(repro::Results& r, const PlantedCliqueStudy& study,
                                 CliqueScaleTally& tally) {
  for (std::size_t c = 0; c < study.cells.size(); ++c) {
    const auto& cell = study.cells[c];
    const auto name = planted_cell_path(cell);
    const auto c_r = r.at(name);
    c_r.metric("k", cell.k);
    c_r.metric("omega0", cell.omega0);
    c_r.metric("planted_is_maximum", cell.planted_is_maximum() ? 1.0 : 0.0);
    record_clique_group(r, name, study.outcomes, c * study.seeds, (c + 1) * study.seeds, cell.k, tally);
  }
  r.metric("planted.cells", static_cast<double>(study.cells.size()));
  r.metric("planted.seeds", static_cast<double>(study.seeds));
}

repro::Figure planted_clique_figure(const PlantedCliqueStudy& study, const PlantedCliqueStudyOptions& options,
                                    double fraction, std::string file) {
  repro::Figure fig;
  fig.file = std::move(file);
  fig.title = fmt::format(
      "Planted clique of {:g} % of n: mean wall time per graph (machine-dependent) and recall of the "
      "planted set",
      100 * fraction);
  fig.cols = static_cast<int>(options.densities.size());
  fig.rows = 2;
  fig.width = 5.0 * fig.cols;
  fig.height = 9.0;
  const char* colors[] = {"tab:blue", "tab:green", "tab:orange"};
  const char* markers[] = {"o", "s", "^"};
  std::vector<repro::Panel> time_panels, recall_panels;
  for (double dens : options.densities) {
    repro::Panel tp, rp;
    tp.title = rp.title = fmt::format("p = {:g}", dens);
    tp.xlabel = rp.xlabel = "candidates n";
    tp.ylabel = "mean wall time (s)";
    rp.ylabel = "recall of the planted clique";
    tp.xscale = tp.yscale = rp.xscale = "log";
    rp.ylim = std::pair{0.0, 1.05};
    tp.legend = "upper left";
    rp.legend = "none";
    for (std::size_t k = 0; k < kCliqueScaleMethods; ++k) {
      const auto meth = kAllCliqueScaleMethods[k];
      std::vector<double> xs, rec;
      std::vector<std::string> tn;
      for (std::size_t c = 0; c < study.cells.size(); ++c) {
        const auto& cell = study.cells[c];
        const int kk = std::max(options.clique_min, static_cast<int>(std::lround(fraction * cell.n)));
        if (cell.p != dens || cell.k != std::min(cell.n, kk)) continue;
        xs.push_back(cell.n);
        tn.push_back(planted_cell_path(cell).under(to_string(meth)).key("time_s"));
        rec.push_back(
            summarize_clique_method(study.outcomes, c * study.seeds, (c + 1) * study.seeds, meth).recall);
      }
      auto l = repro::line_layer(xs, {}, std::string(to_string(meth)), colors[k], markers[k]);
      l.y_timings = tn;
      tp.layers.push_back(l);
      rp.layers.push_back(repro::line_layer(xs, rec, std::string(to_string(meth)), colors[k], markers[k]));
    }
    time_panels.push_back(tp);
    recall_panels.push_back(rp);
  }
  for (auto& pnl : time_panels) fig.panels.push_back(pnl);
  for (auto& pnl : recall_panels) fig.panels.push_back(pnl);
  return fig;
}

// ---------------------------------------------------------------------------------------------------------------
// The study of ext_clique_scale

CliqueScale::Options CliqueScale::Options::read(const core::ConfigTable& p) {
  Options o;
  PlantedCliqueStudyOptions& po = o.planted;
  po.methods.exact_node_limit = static_cast<long long>(p.count("exact_node_limit"));
  po.methods.reference_max_vertices = static_cast<int>(p.integer("reference_max_vertices"));
  for (double n : p.numbers("sizes")) po.sizes.push_back(static_cast<int>(n));
  po.clique_fractions = p.numbers("clique_fractions");
  po.clique_min = static_cast<int>(p.integer("clique_min"));
  po.densities = p.numbers("densities");
  po.seeds = p.count("seeds");
  // 1D worlds of §2.7.1 with exactly `world1d_measurements` measurements (the fractions of Fig. 2.3).
  World1DCliqueOptions& wo = o.world1d;
  wo.methods = po.methods;
  const auto w1 = p.table("world1d");
  const auto world_base = read_world1d_options(w1, false);
  o.world1d_measurements = static_cast<int>(w1.count("measurements"));
  const double inlier_fraction = w1.number("inlier_fraction"),
               aliased_fraction = w1.number("aliased_fraction");
  const double w1_p = w1.number("pcm_p");
  wo.worlds = p.count("world1d_worlds");
  // The Table 2.1 data sets (ch2_table2_1_city's scenario and candidate seed).
  const auto city = p.table("city");
  o.city_datasets = p.count("city_datasets");
  o.city_p = city.number("pcm_p");
  o.city_seed = static_cast<std::uint64_t>(city.integer("seed"));
  o.city_candidates = read_candidate_options(city);
  o.city = ScenarioFiles::read(city);
  o.figure_clique_fraction = p.number("figure_clique_fraction");
  try {
    wo.world = sim::world1d_options_with_total(world_base, o.world1d_measurements, inlier_fraction,
                                               aliased_fraction);
    wo.gamma = pcm::consistency_threshold(w1_p, sim::kWorld1DDof);
    po.validate();
    wo.validate();
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError(fmt::format("{}: {}", p.file(), e.what()));
  }
  return o;
}

CliqueScale::Outcome CliqueScale::run(const Options& o, const repro::RunContext& context) {
  Outcome out;
  out.options = o;
  const auto scenario = load_scenario_2d(o.city);
  core::Progress progress =
      context.progress(o.planted.cells().size() * o.planted.seeds + o.world1d.worlds + o.city_datasets);
  // Planted cliques.
  auto t0 = core::Clock::now();
  out.planted = run_planted_clique_study(o.planted, context, &progress);
  out.planted_time_s = core::seconds_since(t0);
  // 1D worlds, on streams apart from the planted graphs'.
  t0 = core::Clock::now();
  out.worlds = run_world1d_clique_study(
      o.world1d, context.with_streams(context.streams().offset(std::uint64_t{1} << 48)), &progress);
  out.world1d_time_s = core::seconds_since(t0);
  // The Table 2.1 candidate sets.
  t0 = core::Clock::now();
  const auto local = solve_local_pair(scenario);
  out.city = run_two_robot_clique_study(scenario, local, o.city_candidates, o.city_p, pcm::Composition::joint,
                                        o.planted.methods, context.with_streams(core::Streams(o.city_seed)),
                                        o.city_datasets, &progress);
  out.city_time_s = core::seconds_since(t0);
  progress.finish();
  return out;
}

void CliqueScale::record(repro::Results& r, const Outcome& out) {
  const Options& o = out.options;
  CliqueScaleTally tally;
  r.timing("planted", out.planted_time_s);
  record_planted_clique_study(r, out.planted, tally);

  r.timing("world1d", out.world1d_time_s);
  r.metric("world1d.worlds", static_cast<double>(o.world1d.worlds));
  r.metric("world1d.gamma", o.world1d.gamma);
  const double m = o.world1d_measurements;
  double edges = 0;
  for (const auto& w : out.worlds) edges += static_cast<double>(w.edges);
  r.metric("world1d.density", edges / static_cast<double>(out.worlds.size()) / (0.5 * m * (m - 1.0)));
  record_clique_group(r, repro::path("world1d"), out.worlds, 0, out.worlds.size(), 0, tally);

  r.timing("city", out.city_time_s);
  r.metric("city.datasets", static_cast<double>(o.city_datasets));
  r.metric("city.candidates", static_cast<double>(out.city.front().vertices));
  edges = 0;
  for (const auto& s : out.city)
    edges += static_cast<double>(s.edges) / (0.5 * s.vertices * (s.vertices - 1.0));
  r.metric("city.density", edges / static_cast<double>(out.city.size()));
  record_clique_group(r, repro::path("city"), out.city, 0, out.city.size(), 0, tally);

  // Over every graph of the three families.
  tally.record(r, o.planted.methods.reference_max_vertices);
}

std::vector<repro::Figure> CliqueScale::figures(const Outcome& out) {
  return {
      planted_clique_figure(out.planted, out.options.planted, out.options.figure_clique_fraction, ".png")};
}

}  // namespace keel::study::ch2
