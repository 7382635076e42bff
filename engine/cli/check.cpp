// keel check FILE — what a pose-graph file holds (counts, components, noise levels), or the located error.
import keel.core;
import keel.pgo;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

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

}  // namespace

void add_check_command(CLI::App& app) {
  auto a = std::make_shared<CheckArgs>();
  auto* c = app.add_subcommand("check", "read a pose-graph file (g2o or iSAM, 2D or 3D) and summarize it");
  c->group("Your data");
  c->add_option("file", a->file, "the graph file")->required();
  add_common(c, a->common);
  c->callback([a] { run_check(*a); });
}

}  // namespace keel::cli
