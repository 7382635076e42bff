// The `keel` commands that run keel on a researcher's own files (docs/USING.md):
//   keel check FILE                 what the file holds, or the located error
//   keel solve FILE                 batch maximum likelihood (keel.pgo, Ceres)
//   keel marginals FILE             joint Lie-algebra marginal covariances at the solution (keel.cov, ch. 5)
//   keel pcm --a A --b B --candidates C    the two-robot selection of thesis §2.6 (keel.app)
//   keel split GRAPH --ground-truth T      a two-robot split with generated outliers (the Table 2.1 set-up)
// Progress goes to stderr (one line per stage, with the elapsed time) unless --quiet; --json prints one JSON
// document on stdout instead of the text summary.
import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.pcm;
import keel.sim;
import keel.merge;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"

namespace keel::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Stage lines on stderr: "keel solve [0.4 s] solving …".
class Stages {
 public:
  Stages(const char* command, bool quiet) : command_(command), quiet_(quiet), t0_(core::Clock::now()) {}
  void operator()(std::string_view stage) const {
    if (quiet_) return;
    fmt::print(stderr, "keel {} [{:.1f} s] {}\n", command_, elapsed(), stage);
    std::fflush(stderr);
  }
  double elapsed() const { return core::seconds_since(t0_); }

 private:
  const char* command_;
  bool quiet_;
  core::Clock::time_point t0_;
};

void add_common(CLI::App* c, Common& o) {
  c->add_flag("--quiet,-q", o.quiet, "no progress lines on stderr");
  c->add_flag("--json", o.json, "print one JSON document on stdout instead of the text summary");
}

void write_json(const fs::path& file, const json& j) {
  std::ofstream out(file);
  if (!out) throw std::invalid_argument(fmt::format("cannot write '{}'", file.string()));
  out << j.dump() << '\n';
  if (!out) throw std::runtime_error(fmt::format("writing '{}' failed", file.string()));
}

template <class M>
json matrix_json(const M& m) {
  json rows = json::array();
  for (int r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

json summary_json(const pgo::Summary& s) {
  return {{"termination", std::string(pgo::to_string(s.termination))},
          {"message", s.message},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost},
          {"final_chi2", s.final_chi2},
          {"normalized_chi2", s.normalized_chi2},
          {"iterations", s.iterations},
          {"total_time_s", s.total_time_s}};
}

// ---------------------------------------------------------------------------------------------------------------
// keel check

struct CheckArgs {
  Common common;
  std::string file;
};

void run_check(const CheckArgs& a) {
  const auto s = app::summarize(a.file);
  if (a.common.json) {
    fmt::print("{}\n", json{{"file", s.file},
                            {"format", s.format},
                            {"dimension", s.dimension},
                            {"poses", s.poses},
                            {"edges", s.edges},
                            {"odometry", s.odometry},
                            {"loop_closures", s.loop_closures},
                            {"duplicate_edges", s.duplicate_edges},
                            {"landmarks", s.landmarks},
                            {"landmark_measurements", s.landmark_measurements},
                            {"has_initial_poses", s.has_initial_poses},
                            {"components", s.components},
                            {"largest_component", s.largest_component},
                            {"cross_term_edges", s.cross_term_edges},
                            {"sigma_translation", {s.sigma_translation_min, s.sigma_translation_max}},
                            {"sigma_rotation", {s.sigma_rotation_min, s.sigma_rotation_max}},
                            {"condition_max", s.condition_max}}
                           .dump(1));
    return;
  }
  fmt::print("file         {}\n", s.file);
  fmt::print("format       {}, {}D\n", s.format, s.dimension);
  fmt::print("poses        {} (initial estimate: {})\n", s.poses,
             s.has_initial_poses ? "vertices in the file" : "chained odometry");
  fmt::print("edges        {}: {} odometry, {} loop closures, {} duplicates\n", s.edges, s.odometry,
             s.loop_closures, s.duplicate_edges);
  if (s.dimension == 2)
    fmt::print("landmarks    {} ({} measurements)\n", s.landmarks, s.landmark_measurements);
  if (s.components == 1) {
    fmt::print("connected    yes (one component)\n");
  } else {
    fmt::print(
        "connected    NO: {} components, the largest holds {} of {} variables (a solve fixes pose 0; the "
        "other components are undetermined)\n",
        s.components, s.largest_component, s.poses + s.landmarks);
  }
  fmt::print(
      "information  symmetric positive definite (checked on reading); cross terms in {} of {} edges; "
      "condition number ≤ {:.3g}\n",
      s.cross_term_edges, s.edges, s.condition_max);
  fmt::print("noise        σ translation {:.4g} … {:.4g} m, σ rotation {:.4g} … {:.4g} rad (√diag Ω⁻¹)\n",
             s.sigma_translation_min, s.sigma_translation_max, s.sigma_rotation_min, s.sigma_rotation_max);
}

// ---------------------------------------------------------------------------------------------------------------
// keel solve / keel marginals: the solve they share.

struct SolveArgs {
  Common common;
  std::string file, out;
  std::string init = "odometry", robust = "none";
  double robust_param = 5.0;
  std::uint64_t seed = 0;
  unsigned threads = 1;
  int max_iterations = 100;
};

void add_solve_options(CLI::App* c, SolveArgs& a) {
  c->add_option("--init", a.init, "initial estimate: odometry, as-read (the file's vertices) or random")
      ->capture_default_str();
  c->add_option("--seed", a.seed, "seed of --init random")->capture_default_str();
  c->add_option("--robust", a.robust, "robust kernel on the loop closures: none, huber, cauchy or dcs")
      ->capture_default_str();
  c->add_option("--robust-param", a.robust_param, "Huber/Cauchy a or DCS φ")->capture_default_str();
  c->add_option("--threads", a.threads,
                "Ceres threads (the last bits of the result depend on it); 0 = all cores")
      ->capture_default_str();
  c->add_option("--max-iterations", a.max_iterations, "trust-region iterations")->capture_default_str();
}

pgo::Options solver_options(const SolveArgs& a) {
  return app::solve_options(a.init, a.robust, a.robust_param, a.seed, a.threads, a.max_iterations);
}

void check_solved(const pgo::Summary& s) {
  if (s.termination == pgo::Termination::failure)
    throw CommandFailed(fmt::format("the solve failed: {}", s.message));
}

void print_solve_summary(const std::string& file, const pgo::Summary& s, std::size_t poses) {
  fmt::print("solved       {} ({} poses)\n", file, poses);
  fmt::print("termination  {} after {} iterations ({})\n", pgo::to_string(s.termination), s.iterations,
             s.message);
  fmt::print("cost         {:.10g} (initial {:.10g}); χ² {:.10g}; normalized χ² {:.6g}\n", s.final_cost,
             s.initial_cost, s.final_chi2, s.normalized_chi2);
  fmt::print("time         {:.3f} s\n", s.total_time_s);
}

// Writes the graph with the solution as its initial estimate: the format of --out's extension (.g2o or .txt),
// otherwise the input's.
template <class Graph>
void write_solution(Graph g, const fs::path& out, const fs::path& input) {
  const auto ext = out.extension();
  if (ext != ".g2o" && ext != ".txt") {
    const auto text = [&] {
      std::ifstream in(input);
      return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }();
    const auto format = graph::detect_graph_format(text, input).value_or(graph::GraphFormat::g2o);
    if (format == graph::GraphFormat::g2o) {
      graph::write_g2o(g, out);
    } else {
      graph::write_isam(g, out);
    }
    return;
  }
  graph::write_pose_graph(g, out);
}

template <class Graph>
void solve_file(const SolveArgs& a, const Graph& g, const Stages& stage) {
  const auto options = solver_options(a);
  stage(fmt::format("solving ({} poses, {} edges, init {})", g.poses.size(), g.edges.size(), a.init));
  const auto r = pgo::optimize(g, options);
  check_solved(r.summary);
  if (!a.out.empty()) {
    Graph solved = g;
    solved.poses = r.estimate.poses;
    if constexpr (requires { solved.landmarks; }) solved.landmarks = r.estimate.landmarks;
    write_solution(solved, a.out, a.file);
    stage(fmt::format("wrote {}", a.out));
  }
  if (a.common.json) {
    json j = {{"file", a.file},
              {"poses", g.poses.size()},
              {"edges", g.edges.size()},
              {"summary", summary_json(r.summary)}};
    if (!a.out.empty()) j["out"] = a.out;
    fmt::print("{}\n", j.dump(1));
  } else {
    print_solve_summary(a.file, r.summary, g.poses.size());
    if (!a.out.empty()) fmt::print("written      {}\n", a.out);
  }
}

void run_solve(const SolveArgs& a) {
  const Stages stage("solve", a.common.quiet);
  stage(fmt::format("reading {}", a.file));
  if (app::graph_dimension(a.file) == 2) {
    solve_file(a, graph::read_pose_graph_2d(a.file), stage);
  } else {
    solve_file(a, graph::read_pose_graph_3d(a.file), stage);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// keel marginals

struct MarginalsArgs {
  SolveArgs solve;
  std::string pairs, poses;
};

// "i:j,k:l" or a file of "i j" lines.
std::vector<std::pair<int, int>> parse_pairs(const std::string& spec) {
  std::vector<std::pair<int, int>> out;
  if (fs::exists(spec)) {
    std::ifstream in(spec);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      int i = 0, j = 0;
      char extra = 0;
      if (std::sscanf(line.c_str(), "%d %d %c", &i, &j, &extra) != 2 || i < 0 || j < 0) {
        throw std::invalid_argument(
            fmt::format("{}:{}: expected two non-negative pose ids 'i j', got '{}'", spec, number, line));
      }
      out.emplace_back(i, j);
    }
    if (out.empty()) throw std::invalid_argument(fmt::format("{}: no pair", spec));
    return out;
  }
  std::size_t start = 0;
  while (start <= spec.size()) {
    const auto end = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, end - start);
    int i = 0, j = 0;
    char extra = 0;
    if (std::sscanf(item.c_str(), "%d:%d%c", &i, &j, &extra) != 2 || i < 0 || j < 0) {
      throw std::invalid_argument(fmt::format(
          "--pairs: '{}' is not a pair 'i:j' of pose ids (give 'i:j,k:l' or a file of 'i j' lines)", item));
    }
    out.emplace_back(i, j);
    start = end + 1;
  }
  return out;
}

// "0,5,9" with ranges "10-20" (inclusive).
std::vector<int> parse_ids(const std::string& spec) {
  std::vector<int> out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const auto end = std::min(spec.find(',', start), spec.size());
    const std::string item = spec.substr(start, end - start);
    int a = 0, b = 0;
    char extra = 0;
    const int n = std::sscanf(item.c_str(), "%d-%d%c", &a, &b, &extra);
    if (n == 1 && a >= 0) {
      out.push_back(a);
    } else if (n == 2 && a >= 0 && b >= a) {
      for (int k = a; k <= b; ++k) out.push_back(k);
    } else {
      throw std::invalid_argument(
          fmt::format("--poses: '{}' is not a pose id or a range 'a-b' (give e.g. '0,5,10-20')", item));
    }
    start = end + 1;
  }
  return out;
}

template <class Graph>
void check_pose_ids(const Graph& g, const std::vector<int>& ids, const char* what) {
  for (int id : ids) {
    if (id >= static_cast<int>(g.poses.size())) {
      throw std::invalid_argument(fmt::format("{}: pose {} is not in the graph (it has {} poses: 0 … {})",
                                              what, id, g.poses.size(), g.poses.size() - 1));
    }
  }
}

template <class Graph>
void marginals_file(const MarginalsArgs& a, const Graph& g, const Stages& stage) {
  const auto& sa = a.solve;
  const bool planar = std::is_same_v<Graph, graph::PoseGraph2D>;
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> ids;
  if (!a.pairs.empty()) {
    pairs = parse_pairs(a.pairs);
    std::vector<int> flat;
    for (auto [i, j] : pairs) {
      flat.push_back(i);
      flat.push_back(j);
    }
    check_pose_ids(g, flat, "--pairs");
  } else {
    ids = parse_ids(a.poses);
    check_pose_ids(g, ids, "--poses");
  }
  const auto options = solver_options(sa);
  stage(fmt::format("solving ({} poses, {} edges, init {})", g.poses.size(), g.edges.size(), sa.init));
  const auto r = pgo::optimize(g, options);
  check_solved(r.summary);
  stage("information matrix at the solution and its Cholesky factorization (gauge: pose 0 fixed)");
  cov::SparseInformation H = [&] {
    if constexpr (planar) {
      return cov::information_matrix(g, r.estimate.poses, r.estimate.landmarks);
    } else {
      return cov::information_matrix(g, r.estimate.poses);
    }
  }();
  const cov::MarginalCovariance covariance(H);
  const unsigned threads = sa.threads;
  json out = {{"file", sa.file},
              {"dimension", planar ? 2 : 3},
              {"gauge", "pose 0 fixed"},
              {"perturbation", planar ? "left, T = exp(ξ^) T̄, ξ = (ρx, ρy, θ)"
                                      : "left, T = exp(ξ^) T̄, ξ = (ρ, φ) (translation part first)"},
              {"solve", summary_json(r.summary)}};
  const auto t0 = core::Clock::now();
  if (!pairs.empty()) {
    stage(fmt::format("joint marginals of {} pairs", pairs.size()));
    json list = json::array();
    if constexpr (planar) {
      const auto blocks = cov::pair_marginals_2d(covariance, pairs, threads);
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        list.push_back(
            {{"i", pairs[k].first}, {"j", pairs[k].second}, {"covariance", matrix_json(blocks[k])}});
      }
    } else {
      std::vector<std::vector<int>> queries;
      for (auto [i, j] : pairs) queries.push_back({i, j});
      const auto blocks = covariance.joint_many(queries, threads);
      for (std::size_t k = 0; k < pairs.size(); ++k) {
        list.push_back(
            {{"i", pairs[k].first}, {"j", pairs[k].second}, {"covariance", matrix_json(blocks[k])}});
      }
    }
    out["pairs"] = list;
  } else {
    stage(fmt::format("joint marginal of {} poses", ids.size()));
    out["poses"] = ids;
    out["covariance"] = matrix_json(covariance.joint(ids));
  }
  const double extraction_time_s = core::seconds_since(t0);
  out["factorization_time_s"] = covariance.summary().analyze_time_s + covariance.summary().factorize_time_s;
  out["extraction_time_s"] = extraction_time_s;
  if (!sa.out.empty()) {
    write_json(sa.out, out);
    stage(fmt::format("wrote {}", sa.out));
  }
  if (sa.common.json) {
    if (sa.out.empty())
      fmt::print("{}\n", out.dump());
    else
      fmt::print("{}\n", json{{"out", sa.out}, {"solve", out["solve"]}}.dump(1));
    return;
  }
  print_solve_summary(sa.file, r.summary, g.poses.size());
  fmt::print(
      "marginals    {} ({}), gauge pose 0 fixed, left perturbation; factorization {:.3f} s, extraction "
      "{:.3f} s\n",
      pairs.empty() ? fmt::format("joint of {} poses", ids.size())
                    : fmt::format("{} pair{}", pairs.size(), pairs.size() == 1 ? "" : "s"),
      planar ? "ξ = (ρx, ρy, θ)" : "ξ = (ρ, φ)", out["factorization_time_s"].get<double>(),
      extraction_time_s);
  // The first block on screen; all of them in --out.
  const json& first = pairs.empty() ? out["covariance"] : out["pairs"][0]["covariance"];
  fmt::print("{}\n", pairs.empty()
                         ? fmt::format("covariance of poses {}:", a.poses)
                         : fmt::format("covariance of pair {}:{} (Σ_ii Σ_ij; Σ_ji Σ_jj):", pairs[0].first,
                                       pairs[0].second));
  const std::size_t shown = std::min<std::size_t>(first.size(), 12);
  for (std::size_t r0 = 0; r0 < shown; ++r0) {
    std::string line = " ";
    for (std::size_t c = 0; c < std::min<std::size_t>(first[r0].size(), 12); ++c) {
      line += fmt::format(" {:>11.4e}", first[r0][c].get<double>());
    }
    fmt::print("{}\n", line);
  }
  if (sa.out.empty())
    fmt::print("(write every block with --out FILE.json)\n");
  else
    fmt::print("written      {}\n", sa.out);
}

void run_marginals(const MarginalsArgs& a) {
  if (a.pairs.empty() == a.poses.empty()) {
    throw CLI::ValidationError("marginals", "give exactly one of --pairs and --poses");
  }
  const Stages stage("marginals", a.solve.common.quiet);
  stage(fmt::format("reading {}", a.solve.file));
  if (app::graph_dimension(a.solve.file) == 2) {
    marginals_file(a, graph::read_pose_graph_2d(a.solve.file), stage);
  } else {
    marginals_file(a, graph::read_pose_graph_3d(a.solve.file), stage);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// keel pcm

struct PcmArgs {
  Common common;
  std::string a, b, candidates, labels, merged, out;
  double p = 0.11;
  std::string composition = "joint", algorithm = "exact";
  double time_limit_s = 0.0;
  unsigned threads = 1;
};

template <class Run>
void report_pcm(const PcmArgs& args, const Run& run, const Stages& stage) {
  const auto& sel = run.selection;
  const auto& search = *sel.search;
  const int n = run.q.n;
  // Q statistics: how many pairs are consistent, and each selected candidate's consistent partners.
  int consistent_pairs = 0;
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  for (int u = 0; u < n; ++u) {
    for (int v = u + 1; v < n; ++v) {
      if (run.q.at(u, v) <= run.gamma && run.q.at(v, u) <= run.gamma) {
        ++consistent_pairs;
        ++degree[static_cast<std::size_t>(u)];
        ++degree[static_cast<std::size_t>(v)];
      }
    }
  }
  const long long all_pairs = static_cast<long long>(n) * (n - 1) / 2;
  json selected = json::array();
  for (int k : sel.selected) {
    const auto& c = run.candidates[static_cast<std::size_t>(k)];
    selected.push_back({{"candidate", k}, {"pose_a", c.pose_a}, {"pose_b", c.pose_b}});
  }
  json j = {{"candidates", n},
            {"dof", run.q.dof},
            {"p", args.p},
            {"gamma", run.gamma},
            {"composition", args.composition},
            {"algorithm", args.algorithm},
            {"selected", selected},
            {"status", std::string(keel::core::to_string(search.status))},
            {"upper_bound", search.upper_bound},
            {"consistent_pairs", consistent_pairs},
            {"pairs", all_pairs},
            {"local_solve_time_s", {run.a.solve_time_s, run.b.solve_time_s}},
            {"marginals_time_s", run.marginals_time_s},
            {"consistency_time_s", run.consistency_time_s},
            {"selection_time_s", sel.time_s}};
  std::optional<std::pair<double, double>> rates;
  if (!args.labels.empty()) {
    const auto inlier = app::read_labels(args.labels);
    if (static_cast<int>(inlier.size()) != n) {
      throw std::invalid_argument(
          fmt::format("{}: {} labels for {} candidates", args.labels, inlier.size(), n));
    }
    int tp = 0, fp = 0, inliers = 0;
    for (int k = 0; k < n; ++k) inliers += inlier[static_cast<std::size_t>(k)] ? 1 : 0;
    for (int k : sel.selected) (inlier[static_cast<std::size_t>(k)] ? tp : fp) += 1;
    const double tpr = inliers ? static_cast<double>(tp) / inliers : 1.0;
    const double fpr = n - inliers ? static_cast<double>(fp) / (n - inliers) : 0.0;
    rates = {tpr, fpr};
    j["true_positives"] = tp;
    j["false_positives"] = fp;
    j["tpr"] = tpr;
    j["fpr"] = fpr;
  }
  if (run.merged) {
    j["merged"] = {{"file", args.merged}, {"summary", summary_json(run.merged->summary)}};
  }
  if (!args.out.empty()) {
    json full = j;
    full["q"] = run.q.q;
    write_json(args.out, full);
    stage(fmt::format("wrote {}", args.out));
  }
  if (args.common.json) {
    fmt::print("{}\n", j.dump(1));
    return;
  }
  fmt::print("candidates   {} ({}D, {} dof per loop error)\n", n, run.q.dof == 3 ? 2 : 3, run.q.dof);
  fmt::print("threshold    γ = {:.6g} (p = {}, χ²({}) tail), {} composition\n", run.gamma, args.p, run.q.dof,
             args.composition);
  fmt::print("consistent   {} of {} pairs ({:.2f} %)\n", consistent_pairs, all_pairs,
             all_pairs ? 100.0 * consistent_pairs / all_pairs : 0.0);
  fmt::print("selected     {} candidates: {} ({}, bound {})\n", sel.selected.size(),
             fmt::join(sel.selected, " "), keel::core::to_string(search.status), search.upper_bound);
  if (!search.proven_optimal()) {
    fmt::print("             not proven maximum: a larger consistent set may exist (at most {})\n",
               search.upper_bound);
  }
  if (rates) {
    fmt::print("labels       TPR {:.4f}, FPR {:.4f} ({} true, {} false positives)\n", rates->first,
               rates->second, j["true_positives"].get<int>(), j["false_positives"].get<int>());
  }
  fmt::print("time         local solves {:.3f} + {:.3f} s, marginals {:.3f} s, Q {:.3f} s, clique {:.3f} s\n",
             run.a.solve_time_s, run.b.solve_time_s, run.marginals_time_s, run.consistency_time_s,
             sel.time_s);
  if (run.merged) {
    fmt::print("merged       {} ({} poses); normalized χ² {:.6g}\n", args.merged,
               run.merged->poses_a.size() + run.merged->poses_b.size(), run.merged->summary.normalized_chi2);
  }
  if (!args.out.empty()) fmt::print("written      {}\n", args.out);
}

void run_pcm_command(const PcmArgs& args) {
  const Stages stage("pcm", args.common.quiet);
  app::PcmOptions o;
  o.p = args.p;
  o.composition = pcm::composition_from_string(args.composition);
  o.algorithm = pcm::clique_algorithm_from_string(args.algorithm);
  o.time_limit_s = args.time_limit_s;
  o.threads = args.threads;
  o.merge = !args.merged.empty();
  const app::Progress progress = [&](std::string_view s) { stage(s); };
  stage(fmt::format("reading {}, {} and {}", args.a, args.b, args.candidates));
  if (app::graph_dimension(args.a) == 2) {
    const auto run = app::run_pcm(graph::read_pose_graph_2d(args.a), graph::read_pose_graph_2d(args.b),
                                  graph::read_g2o_edges_2d(args.candidates), o, progress);
    if (run.merged) {
      check_solved(run.merged->summary);
      graph::write_pose_graph(app::merged_graph(run), args.merged);
    }
    report_pcm(args, run, stage);
  } else {
    const auto run = app::run_pcm(graph::read_pose_graph_3d(args.a), graph::read_pose_graph_3d(args.b),
                                  graph::read_g2o_edges_3d(args.candidates), o, progress);
    if (run.merged) {
      check_solved(run.merged->summary);
      graph::write_pose_graph(app::merged_graph(run), args.merged);
    }
    report_pcm(args, run, stage);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// keel split

struct SplitArgs {
  Common common;
  std::string graph, ground_truth, out_dir;
  app::SplitFilesOptions options;
};

void run_split(const SplitArgs& a) {
  const Stages stage("split", a.common.quiet);
  stage(fmt::format("reading {} and {}", a.graph, a.ground_truth));
  if (app::graph_dimension(a.graph) != 2) {
    throw std::invalid_argument(fmt::format("{}: keel split supports 2D graphs", a.graph));
  }
  const auto g = graph::read_pose_graph_2d(a.graph);
  const auto truth = graph::read_poses_2d(a.ground_truth);
  const auto set = app::split_files(g, truth, a.options, a.out_dir);
  const int inliers = static_cast<int>(set.inliers().size());
  const auto& s = a.options.split;
  if (a.common.json) {
    fmt::print("{}\n", json{{"out_dir", a.out_dir},
                            {"robot_a", {s.first, s.split}},
                            {"robot_b", {s.split, s.last}},
                            {"candidates", set.candidates.size()},
                            {"inliers", inliers}}
                           .dump(1));
    return;
  }
  fmt::print("robots       a = poses [{}, {}), b = [{}, {})\n", s.first, s.split, s.split, s.last);
  fmt::print("candidates   {} ({} inliers, {} aliased, {} random outliers; seed {})\n", set.candidates.size(),
             inliers, a.options.candidates.aliased_groups * a.options.candidates.aliased_group_size,
             a.options.candidates.random_outliers, a.options.seed);
  fmt::print("written      {}/{{a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt}}\n", a.out_dir);
}

}  // namespace

void add_tool_commands(CLI::App& app) {
  {
    auto a = std::make_shared<CheckArgs>();
    auto* c = app.add_subcommand("check", "read a pose-graph file (g2o or iSAM, 2D or 3D) and summarize it");
    c->group("Your data");
    c->add_option("file", a->file, "the graph file")->required();
    add_common(c, a->common);
    c->callback([a] { run_check(*a); });
  }
  {
    auto a = std::make_shared<SolveArgs>();
    auto* c = app.add_subcommand("solve", "batch maximum-likelihood solve of a pose graph (Ceres)");
    c->group("Your data");
    c->add_option("file", a->file, "the graph file")->required();
    c->add_option("--out", a->out,
                  "write the graph with the solution as its estimate (.g2o or .txt picks the format; other "
                  "names get the input's format)");
    add_solve_options(c, *a);
    add_common(c, a->common);
    c->callback([a] { run_solve(*a); });
  }
  {
    auto a = std::make_shared<MarginalsArgs>();
    auto* c = app.add_subcommand(
        "marginals",
        "joint Lie-algebra marginal covariances at the solution (thesis ch. 5; gauge: pose 0 fixed)");
    c->group("Your data");
    c->add_option("file", a->solve.file, "the graph file")->required();
    c->add_option("--pairs", a->pairs,
                  "pose pairs 'i:j,k:l' or a file of 'i j' lines: one 2d×2d joint per pair");
    c->add_option("--poses", a->poses, "pose ids '0,5,10-20': their joint covariance");
    c->add_option("--out", a->solve.out, "write every covariance to this JSON file");
    add_solve_options(c, a->solve);
    add_common(c, a->solve.common);
    c->callback([a] { run_marginals(*a); });
  }
  {
    auto a = std::make_shared<PcmArgs>();
    auto* c = app.add_subcommand(
        "pcm", "pairwise consistency maximization of inter-robot loop closures (thesis §2.6) on your files");
    c->group("Your data");
    c->add_option("--a", a->a, "robot a's graph (g2o or iSAM)")->required();
    c->add_option("--b", a->b, "robot b's graph")->required();
    c->add_option("--candidates", a->candidates,
                  "candidate loop closures: g2o edges 'EDGE_SE2 i j …' with i a pose of robot a and j a pose "
                  "of robot b (EDGE_SE3:QUAT in 3D)")
        ->required();
    c->add_option("--p", a->p, "χ² tail probability of the consistency threshold γ (thesis PCM-Exact-11 %)")
        ->capture_default_str();
    c->add_option("--composition", a->composition, "joint (eq. 2.4 with the joint marginals) or independent")
        ->capture_default_str();
    c->add_option("--algorithm", a->algorithm, "maximum clique: exact or heuristic")->capture_default_str();
    c->add_option("--time-limit", a->time_limit_s, "stop the exact search after this many seconds (0: none)")
        ->capture_default_str();
    c->add_option("--labels", a->labels, "labels.txt of keel split: score the selection (TPR, FPR)");
    c->add_option("--merged", a->merged,
                  "solve the merged map with the selected candidates and write it here");
    c->add_option("--out", a->out, "write the result and the consistency matrix Q to this JSON file");
    c->add_option("--threads", a->threads, "threads for Q (the result does not depend on it); 0 = all cores")
        ->capture_default_str();
    add_common(c, a->common);
    c->callback([a] { run_pcm_command(*a); });
  }
  {
    auto a = std::make_shared<SplitArgs>();
    auto& o = a->options;
    o.split.first = 0;
    o.split.split = 750;
    o.split.last = 1500;
    auto* c = app.add_subcommand(
        "split",
        "split a single-robot 2D graph with ground truth into two robots and candidate loop closures "
        "with outliers (the set-up of thesis Table 2.1)");
    c->group("Your data");
    c->add_option("graph", a->graph, "the single-robot graph")->required();
    c->add_option("--ground-truth", a->ground_truth, "ground-truth poses, lines 'id x y theta'")->required();
    c->add_option("--out-dir", a->out_dir, "folder for a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt")
        ->required();
    c->add_option("--first", o.split.first, "first pose of robot a")->capture_default_str();
    c->add_option("--split", o.split.split, "first pose of robot b")->capture_default_str();
    c->add_option("--last", o.split.last, "one past the last pose of robot b")->capture_default_str();
    c->add_option("--inliers", o.candidates.num_inliers, "true loop closures drawn")->capture_default_str();
    c->add_option("--aliased-groups", o.candidates.aliased_groups, "groups of mutually consistent outliers")
        ->capture_default_str();
    c->add_option("--aliased-size", o.candidates.aliased_group_size, "outliers per group")
        ->capture_default_str();
    c->add_option("--random-outliers", o.candidates.random_outliers, "random outliers")
        ->capture_default_str();
    c->add_option("--seed", o.seed, "seed of the draw")->capture_default_str();
    add_common(c, a->common);
    c->callback([a] { run_split(*a); });
  }
}

}  // namespace keel::cli
