// keel marginals FILE — joint Lie-algebra marginal covariances at the solution (app::marginals: thesis ch. 5,
// eq. 5.28 from a MAP solution; gauge: pose 0 fixed, or the pose of a g2o FIX line).
// <variant> before the imports: included after them, clang-19 rejects its hash helpers as a redefinition
// (docs/TOOLCHAIN.md).
#include <variant>

import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

namespace fs = std::filesystem;

struct MarginalsArgs {
  SolveArgs solve;
  std::string pairs, poses;
};

// "i:j,k:l" or a file of "i j" lines (read once, so a pipe works); every id through core::parse_integer and
// checked against the graph's pose count, so an id beyond int (4294967297) is refused instead of wrapping.
std::vector<std::pair<int, int>> parse_pairs(const std::string& spec, std::size_t poses) {
  const std::int64_t top = static_cast<std::int64_t>(poses) - 1;
  const std::string expected = fmt::format("a pose id of the graph ({} poses)", poses);
  std::vector<std::pair<int, int>> out;
  std::int64_t i = 0, j = 0;
  if (fs::exists(spec)) {
    const std::string text = core::read_text_file(spec);
    int number = 0;
    for (std::string_view line : core::split_fields(text, '\n')) {
      ++number;
      if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      std::vector<std::string_view> f;
      for (std::string_view t : core::split_fields(line, ' '))
        for (std::string_view u : core::split_fields(t, '\t')) {
          while (!u.empty() && u.back() == '\r') u.remove_suffix(1);
          if (!u.empty()) f.push_back(u);
        }
      if (f.empty()) continue;
      if (f.size() != 2) {
        throw std::invalid_argument(fmt::format("{}:{}: expected two pose ids 'i j', got {} field{}", spec,
                                                number, f.size(), f.size() == 1 ? "" : "s"));
      }
      for (int k = 0; k < 2; ++k) {
        if (auto why = core::parse_integer(f[static_cast<std::size_t>(k)], 0, top, k == 0 ? i : j, expected);
            !why.empty())
          throw std::invalid_argument(fmt::format("{}:{}: field {}: {}", spec, number, k + 1, why));
      }
      out.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
    if (out.empty()) throw std::invalid_argument(fmt::format("{}: no pair", spec));
    return out;
  }
  for (const std::string_view item : core::split_fields(spec, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string_view::npos) {
      throw std::invalid_argument(
          fmt::format("--pairs: {} is not a pair 'i:j' of pose ids (give 'i:j,k:l' or a file of 'i j' lines)",
                      core::quote_token(item)));
    }
    for (int k = 0; k < 2; ++k) {
      const std::string_view t = k == 0 ? item.substr(0, colon) : item.substr(colon + 1);
      if (auto why = core::parse_integer(t, 0, top, k == 0 ? i : j, expected); !why.empty())
        throw std::invalid_argument(fmt::format("--pairs: pair {}: {}", core::quote_token(item), why));
    }
    out.emplace_back(static_cast<int>(i), static_cast<int>(j));
  }
  return out;
}

// "0,5,9" with ranges "10-20" (inclusive), every id below the pose count and at most that many ids in all,
// checked before the list is expanded.
std::vector<int> parse_ids(const std::string& spec, std::size_t poses) {
  const auto n = static_cast<std::int64_t>(poses);
  return core::parse_id_list(spec, n, n, "--poses", fmt::format("a pose id of the graph ({} poses)", poses));
}

template <class Graph>
void marginals_file(const MarginalsArgs& a, const Graph& g, const Stages& stage, app::Outputs& outputs) {
  const auto& sa = a.solve;
  const bool planar = std::is_same_v<Graph, graph::PoseGraph2D>;
  app::MarginalsRequest request;
  request.threads = sa.likelihood.options.threads;
  if (!a.pairs.empty()) {
    request.pairs = parse_pairs(a.pairs, g.poses.size());
  } else {
    request.ids = parse_ids(a.poses, g.poses.size());
  }
  stage(fmt::format("solving ({} poses, {} edges, init {})", g.poses.size(), g.edges.size(), sa.init));
  const auto solved = app::solve(g, sa.likelihood);
  check_solved(solved.summary);
  const auto m = [&] {
    if constexpr (planar) {
      return app::marginals(g, pgo::Estimate2D{solved.graph.poses, solved.graph.landmarks}, request,
                            stage.progress());
    } else {
      return app::marginals(g, pgo::Estimate3D{solved.graph.poses}, request, stage.progress());
    }
  }();
  json out = {{"file", sa.file},
              {"dimension", m.dimension},
              {"gauge", fmt::format("pose {} fixed", g.gauge_pose)},
              {"perturbation", planar ? "left, T = exp(ξ^) T̄, ξ = (ρx, ρy, θ)"
                                      : "left, T = exp(ξ^) T̄, ξ = (ρ, φ) (translation part first)"},
              {"solve", record_json(solved.summary)}};
  if (!request.pairs.empty()) {
    json list = json::array();
    for (std::size_t k = 0; k < request.pairs.size(); ++k) {
      list.push_back({{"i", request.pairs[k].first},
                      {"j", request.pairs[k].second},
                      {"covariance", matrix_json(m.pairs[k])}});
    }
    out["pairs"] = list;
  } else {
    out["poses"] = request.ids;
    out["covariance"] = matrix_json(m.joint);
  }
  out["factorization_time_s"] = m.factor.analyze_time_s + m.factor.factorize_time_s;
  out["factor"] = record_json(m.factor);  // what Python's Marginals.summary holds
  out["extraction_time_s"] = m.extraction_time_s;
  if (!sa.out.empty()) {
    write_json(outputs, sa.out, out);
    outputs.commit();
    stage(fmt::format("wrote {}", sa.out));
  }
  if (sa.common.json) {
    if (sa.out.empty())
      fmt::print("{}\n", out.dump());
    else
      fmt::print("{}\n", json{{"out", sa.out}, {"solve", out["solve"]}}.dump(1));
    return;
  }
  const auto& pairs = request.pairs;
  const auto& ids = request.ids;
  print_solve_summary(sa.file, solved.summary, g.poses.size());
  fmt::print(
      "marginals    {} ({}), gauge pose {} fixed, left perturbation; factorization {:.3f} s, extraction "
      "{:.3f} s\n",
      pairs.empty() ? fmt::format("joint of {} poses", ids.size())
                    : fmt::format("{} pair{}", pairs.size(), pairs.size() == 1 ? "" : "s"),
      planar ? "ξ = (ρx, ρy, θ)" : "ξ = (ρ, φ)", g.gauge_pose, out["factorization_time_s"].get<double>(),
      m.extraction_time_s);
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
  app::Outputs outputs({{"file", a.solve.file}, {"--pairs", a.pairs}});
  if (!a.solve.out.empty()) outputs.file("--out", a.solve.out, app::OutputKind::json());
  stage(fmt::format("reading {}", a.solve.file));
  std::visit([&](const auto& g) { marginals_file(a, g, stage, outputs); }, app::read_graph(a.solve.file));
}

}  // namespace

void add_marginals_command(CLI::App& app) {
  auto a = std::make_shared<MarginalsArgs>();
  auto* c = app.add_subcommand(
      "marginals",
      "joint Lie-algebra marginal covariances at the solution (thesis ch. 5; gauge: pose 0 fixed, or the "
      "pose of a g2o FIX line)");
  c->group("Your data");
  c->add_option("file", a->solve.file, "the graph file")->required();
  c->add_option("--pairs", a->pairs,
                "pose pairs 'i:j,k:l' or a file of 'i j' lines: one 2d×2d joint per pair");
  c->add_option("--poses", a->poses, "pose ids '0,5,10-20': their joint covariance");
  c->add_option("--out", a->solve.out, "write every covariance to this JSON file");
  add_solve_options(c, a->solve);
  add_common(c, a->solve.common);
  c->callback([a] {
    check_solve_options(a->solve);
    run_marginals(*a);
  });
}

}  // namespace keel::cli
