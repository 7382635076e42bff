// keel solve FILE — batch maximum-likelihood solve of a pose graph (app::solve: keel.pgo, Ceres).
// <variant> before the imports: included after them, clang-19 rejects its hash helpers as a redefinition
// (docs/TOOLCHAIN.md).
#include <variant>

import keel.core;
import keel.graph;
import keel.pgo;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "tool_common.hpp"
#include "write_solution.hpp"

namespace keel::cli {

namespace {

namespace fs = std::filesystem;

// The format --out is written in: its extension's (.g2o, .txt), otherwise the input's (read with it, once).
graph::GraphFormat out_format(const SolveArgs& a, graph::GraphFormat input) {
  const auto ext = fs::path(a.out).extension();
  if (ext == ".g2o") return graph::GraphFormat::g2o;
  if (ext == ".txt") return graph::GraphFormat::isam;
  return input;
}

template <class Graph>
void solve_file(const SolveArgs& a, const Graph& g, const app::MaximumLikelihood& backend,
                const Stages& stage, app::Outputs& outputs, graph::GraphFormat format) {
  stage(fmt::format("solving ({} poses, {} edges, init {})", g.poses.size(), g.edges.size(), a.init));
  const auto s = app::solve(g, backend);
  check_solved(s.summary);
  if (!a.out.empty()) {
    outputs.write(a.out, [&](const fs::path& temporary) { write_solution(s.graph, temporary, format); });
    outputs.commit();
    stage(fmt::format("wrote {}", a.out));
  }
  if (a.common.json) {
    json j = {{"file", a.file},
              {"poses", g.poses.size()},
              {"edges", g.edges.size()},
              {"summary", record_json(s.summary)}};
    if (!a.out.empty()) j["out"] = a.out;
    fmt::print("{}\n", j.dump(1));
  } else {
    print_solve_summary(a.file, s.summary, g.poses.size());
    if (!a.out.empty()) fmt::print("written      {}\n", a.out);
  }
}

// Not certified, the command prints what it found and exits 1 (done, but not what was asked) without
// writing --out: outputs are written only on exit 0.
template <class Graph>
void solve_file(const SolveArgs& a, const Graph& g, const app::Certified& backend, const Stages& stage,
                app::Outputs& outputs, graph::GraphFormat format) {
  stage(fmt::format("certified solve ({} poses, {} edges, gap tolerance {:g}, ranks up to {})",
                    g.poses.size(), g.edges.size(), backend.options.gap_tolerance, backend.options.max_rank));
  const auto s = app::solve_certified(g, backend);
  const bool certified = s.summary.certificate.certified;
  const bool written = certified && !a.out.empty();
  if (written) {
    outputs.write(a.out, [&](const fs::path& temporary) { write_solution(s.graph, temporary, format); });
    outputs.commit();
    stage(fmt::format("wrote {}", a.out));
  }
  if (a.common.json) {
    json j = {
        {"file", a.file},
        {"poses", s.summary.poses},
        {"edges", s.summary.edges},
        {"anisotropic_cost", std::isfinite(s.anisotropic_cost) ? json(s.anisotropic_cost) : json(nullptr)},
        {"indefinite_information", g.indefinite_information},
        {"certificate", record_json(s.summary)}};
    if (written) j["out"] = a.out;
    fmt::print("{}\n", j.dump(1));
  } else {
    print_certified_summary(a.file, s.summary, s.anisotropic_cost);
    if (written) fmt::print("written      {}\n", a.out);
  }
  if (!certified)
    throw CommandFailed(fmt::format(
        "{}{}{}", s.summary.message.starts_with("not certified") ? "" : "not certified: ", s.summary.message,
        a.out.empty() ? "" : fmt::format(" ({} not written)", a.out)));
}

void run_solve(const SolveArgs& a) {
  const Stages stage("solve", a.common.quiet);
  app::Outputs outputs({{"file", a.file}});
  if (!a.out.empty()) outputs.file("--out", a.out, app::OutputKind::graph());
  stage(fmt::format("reading {}", a.file));
  // The isotropic model of --certify reads only the diagonal blocks of each information matrix; the
  // anisotropic solve needs all of it and names the option that reads such a file.
  const app::SolveBackend backend = a.backend();
  const auto read = [&] {
    const auto information = app::information_check(backend);
    if (information != graph::InformationCheck::positive_definite)
      return app::read_graph_input(a.file, information);
    try {
      return app::read_graph_input(a.file);
    } catch (const graph::ParseError& e) {
      if (std::string_view(e.what()).find("not positive definite") == std::string_view::npos) throw;
      // An input refused (exit 3), with the option that reads it.
      throw std::invalid_argument(
          fmt::format("{}\n(the anisotropic solve needs every information matrix positive "
                      "definite; `keel solve --certify` reads this file: its isotropic model uses "
                      "only the translation and rotation blocks)",
                      e.what()));
    }
  };
  const app::GraphInput input = read();
  const app::AnyGraph& graph = input.graph;
  const auto format = a.out.empty() ? graph::GraphFormat::g2o : out_format(a, input.format);
  std::visit(
      [&](const auto& g) {
        if (g.indefinite_information > 0)
          fmt::print(
              stderr,
              "keel solve: warning: {} of {} information matrices are not positive definite; the isotropic "
              "model uses only their translation and rotation blocks (positive definite in every edge)\n",
              g.indefinite_information, g.edges.size());
      },
      graph);
  std::visit([&](const auto& g, const auto& b) { solve_file(a, g, b, stage, outputs, format); }, graph,
             backend);
}

}  // namespace

void add_solve_command(CLI::App& app) {
  auto a = std::make_shared<SolveArgs>();
  auto* c = app.add_subcommand("solve", "batch maximum-likelihood solve of a pose graph (Ceres)");
  c->group("Your data");
  c->add_option("file", a->file, "the graph file")->required();
  c->add_option("--out", a->out,
                "write the graph with the solution as its estimate (.g2o or .txt picks the format; other "
                "names get the input's format)");
  add_solve_options(c, *a);
  c->add_flag(
      "--certify", a->certify,
      "solve the isotropic (chordal) model with a global-optimality certificate instead (SE-Sync's "
      "problem: chordal initialization, Riemannian staircase); --init, --seed, --robust, --robust-param, "
      "--threads and --max-iterations do not apply (exit 2 when given)");
  auto& certified = a->certified.options;
  c->add_option("--gap-tolerance", certified.gap_tolerance, "--certify: relative duality gap that certifies")
      ->capture_default_str();
  c->add_option("--max-rank", certified.max_rank, "--certify: the staircase's last rank")
      ->capture_default_str();
  c->add_option(
       "--staircase-stationarity", certified.staircase_stationarity,
       "--certify: above rank d, each rank is first solved until ‖grad‖·‖X‖ ≤ this × max(F, 1), and "
       "solved on only where its rounded answer could still be certified (in [0, 1); 0: every rank to "
       "the full tolerance)")
      ->capture_default_str();
  c->add_option(
       "--staircase-relative-decrease", certified.staircase_relative_decrease,
       "--certify: a rank's loose solve also stops at a trust-region step inside its region that lowers "
       "F by less than this × F (SE-Sync's rule; faster, but an answer may get worse; in [0, 1); 0: off)")
      ->capture_default_str();
  c->add_option("--preconditioner", a->preconditioner,
                "--certify: the trust-region steps' preconditioner above rank d: auto (reduced where the "
                "translations weigh at least F), joint (rotations and translations together) or reduced "
                "(translations eliminated, as SE-Sync)")
      ->capture_default_str();
  auto* time_limit = c->add_option(
      "--time-limit", certified.time_limit_s,
      "--certify: stop after this many seconds (> 0; left out: no limit); the point reached and its rounding "
      "are "
      "tested (a run can exceed the limit by those tests), termination time_limit, exit 1 unless certified");
  add_common(c, a->common);
  c->callback([a, c, time_limit] {
    // An option of the other mode would be ignored silently: the anisotropic solve has no gap, rank or time
    // limit, and the certified solve starts from the chordal initialization with no kernel, Ceres threads or
    // iteration cap of its own. Given, it is a bad command line (exit 2).
    constexpr const char* kSolveOnly[] = {"--init",         "--seed",    "--robust",
                                          "--robust-param", "--threads", "--max-iterations"};
    constexpr const char* kCertifyOnly[] = {"--gap-tolerance",
                                            "--max-rank",
                                            "--time-limit",
                                            "--staircase-stationarity",
                                            "--staircase-relative-decrease",
                                            "--preconditioner"};
    for (const char* name :
         a->certify ? std::span<const char* const>(kSolveOnly) : std::span<const char* const>(kCertifyOnly))
      if (c->get_option(name)->count() > 0)
        throw CLI::ValidationError(
            name, a->certify
                      ? "does not apply with --certify (the certified solve starts from the chordal "
                        "initialization, has no robust kernel and runs on one thread)"
                      : "applies only with --certify (the anisotropic solve has no gap, rank or time limit)");
    check_option("--time-limit", [&] {
      if (time_limit->count() > 0 && !(a->certified.options.time_limit_s > 0.0))
        throw std::invalid_argument(
            fmt::format("{} s: give a time limit > 0 seconds, or leave the option out for no limit",
                        a->certified.options.time_limit_s));
    });
    check_solve_options(*a);
    run_solve(*a);
  });
}

}  // namespace keel::cli
