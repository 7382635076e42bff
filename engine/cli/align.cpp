// keel align REFERENCE QUERY — trajectory alignment without data association (thesis ch. 3) on two surveys
// given as CSV (app::align_surveys); keel align-world DIR — a simulated survey pair of Table 3.1's generator,
// or with --terrain one over a real elevation grid, written as those files (app::write_alignment_world,
// app::write_terrain_world).
import keel.core;
import keel.align;
import keel.pgo;
import keel.sim;
import keel.app;

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "tool_common.hpp"

namespace keel::cli {

namespace {

struct AlignArgs {
  Common common;
  std::string reference, query;
  bool depth = false;
  std::string method = "proposed", dissimilarity = "standardized";
  app::AlignSurveysOptions options;
};

json transform_json(const align::Transform2& t) {
  return {{"a11", t.a11}, {"a12", t.a12}, {"a21", t.a21}, {"a22", t.a22}, {"tx", t.tx}, {"ty", t.ty}};
}

// --certify that did not prove the optimum (a node or time limit, a gap that did not close): exit 1, done but
// not what was asked, after the answer is printed.
void check_certified(const app::SurveyAlignment& s) {
  if (s.certificate && s.certificate->status != core::SearchStatus::optimal)
    throw CommandFailed(
        fmt::format("the optimum over SO(2) is not certified ({}): only the printed bounds are proven",
                    core::to_string(s.certificate->status)));
}

// The option values, each by the engine's own check (check_option: a refusal is exit 2 naming the option),
// before any file is read.
void check_align_options(const AlignArgs& a) {
  check_option("--method", [&] { (void)align::method_from_string(a.method); });
  check_option("--dissimilarity", [&] { (void)app::dissimilarity_from_string(a.dissimilarity); });
  const auto check = [](const char* option, auto set) {
    app::AlignSurveysOptions o;
    set(o);
    check_option(option, [&] { o.validate(); });
  };
  const auto& given = a.options;
  check("--rounds", [&](app::AlignSurveysOptions& o) { o.region.max_rounds = given.region.max_rounds; });
  check("--shrink", [&](app::AlignSurveysOptions& o) { o.region.shrink = given.region.shrink; });
  check("--min-half-width",
        [&](app::AlignSurveysOptions& o) { o.region.min_half_width = given.region.min_half_width; });
  check("--depth-gate", [&](app::AlignSurveysOptions& o) { o.depth_gate = given.depth_gate; });
}

void run_align(AlignArgs a) {
  const Stages stage("align", a.common.quiet);
  a.options.method = align::method_from_string(a.method);
  a.options.dissimilarity = app::dissimilarity_from_string(a.dissimilarity);
  stage(fmt::format("reading {} and {}", a.reference, a.query));
  const app::Survey ref = app::read_survey_csv(a.reference, a.depth);
  const app::Survey query = app::read_survey_csv(a.query, a.depth);
  stage(fmt::format("aligning {} query positions to {} reference positions ({} features, {}, {})",
                    query.size(), ref.size(), ref.dim, a.method, a.dissimilarity));
  const app::SurveyAlignment s = app::align_surveys(ref, query, a.options);
  const align::AlignResult& r = s.result;
  if (a.common.json) {
    json rounds = json::array();
    for (const auto& t : r.rounds)
      rounds.push_back({{"half_width", t.half_width},
                        {"cost", t.cost},
                        {"sector", t.sector},
                        {"kept_boxes", t.kept_boxes},
                        {"transform", transform_json(t.transform)}});
    json j = {{"reference", a.reference},
              {"query", a.query},
              {"method", a.method},
              {"dissimilarity", a.dissimilarity},
              {"reference_points", s.reference_points},
              {"query_points", s.query_points},
              {"transform", transform_json(r.raw)},
              {"rigid", {{"theta", r.rigid.theta}, {"tx", r.rigid.tx}, {"ty", r.rigid.ty}}},
              {"cost", r.cost},
              {"sector", r.sector},
              {"rounds", rounds},
              {"time_s", r.time_s}};
    if (s.certificate) {
      const auto& c = *s.certificate;
      j["certificate"] = {{"status", std::string(core::to_string(c.status))},
                          {"theta", c.theta},
                          {"tx", c.tx},
                          {"ty", c.ty},
                          {"lower_bound", c.bound.lower},
                          {"upper_bound", c.bound.upper},
                          {"relative_gap", c.bound.relative_gap()},
                          {"nodes", c.nodes}};
    }
    fmt::print("{}\n", j.dump(1));
    check_certified(s);
    return;
  }
  constexpr double deg = 180.0 / 3.14159265358979323846;
  fmt::print("method       {} ({} dissimilarity), {} rounds, cost {:.10g}\n", a.method, a.dissimilarity,
             r.rounds.size(), r.cost);
  fmt::print(
      "transform    p_ref = A p_query + t,  A = [[{:.9g}, {:.9g}], [{:.9g}, {:.9g}]],  t = ({:.9g}, "
      "{:.9g})\n",
      r.raw.a11, r.raw.a12, r.raw.a21, r.raw.a22, r.raw.tx, r.raw.ty);
  fmt::print(
      "rigid        θ = {:.9g} rad ({:.6g}°), t = ({:.9g}, {:.9g}) m (closest rotation; the query centroid "
      "kept where A, t put it)\n",
      r.rigid.theta, r.rigid.theta * deg, r.rigid.tx, r.rigid.ty);
  for (std::size_t k = 0; k < r.rounds.size(); ++k) {
    const auto& t = r.rounds[k];
    fmt::print("round {:<2}     half-width {:8.3f} m  cost {:.8g}  θ {:.6g}°\n", k, t.half_width, t.cost,
               std::atan2(t.transform.a21 - t.transform.a12, t.transform.a11 + t.transform.a22) * deg);
  }
  if (s.certificate) {
    const auto& c = *s.certificate;
    fmt::print(
        "certificate  {} over SO(2) for round 0's objective: θ* = {:.9g} rad ({:.6g}°), objective in "
        "[{:.10g}, {:.10g}], {} intervals\n",
        core::to_string(c.status), c.theta, c.theta * deg, c.bound.lower, c.bound.upper, c.nodes);
  }
  check_certified(s);
}

struct WorldArgs {
  Common common;
  std::string dir, terrain;
  std::uint64_t seed = 20181022, index = 0;
  double scale = 50.0;
  sim::AlignmentWorldOptions world;
};

// The option values, each by the engine's own check (check_option: a refusal is exit 2 naming the option),
// before anything is read or written. --scale is checked with or without --terrain.
void check_world_options(const WorldArgs& a) {
  const auto check = [](const char* option, auto set) {
    sim::AlignmentWorldOptions o;
    set(o);
    check_option(option, [&] { o.validate(); });
  };
  const auto& given = a.world;
  check("--feature-noise", [&](sim::AlignmentWorldOptions& o) { o.feature_noise = given.feature_noise; });
  check("--query-size", [&](sim::AlignmentWorldOptions& o) { o.query_size = given.query_size; });
  check("--bump-sigma-min/--bump-sigma-max", [&](sim::AlignmentWorldOptions& o) {
    o.bump_sigma_min = given.bump_sigma_min;
    o.bump_sigma_max = given.bump_sigma_max;
  });
  check("--bumps", [&](sim::AlignmentWorldOptions& o) { o.bumps = given.bumps; });
  check_option("--scale", [&] {
    if (!(a.scale > 0 && std::isfinite(a.scale)))
      throw std::invalid_argument(fmt::format("{}: must be a length > 0 (m)", a.scale));
  });
}

void run_world(WorldArgs a) {
  const Stages stage("align-world", a.common.quiet);
  app::Outputs outputs({{"--terrain", a.terrain}});
  const auto staging = outputs.folder("dir", a.dir, app::world_folder_files());
  app::WorldTruth t;
  json extra = json::object();
  std::string unit = "m";
  if (a.terrain.empty()) {
    stage(fmt::format("world {} of seed {}", a.index, a.seed));
    t = app::write_alignment_world(a.world, a.seed, a.index, staging);
  } else {
    // Table 3.1's geometry (lengths in sample spacings) times the scale, aligned in units of the scale (the
    // settings of ch3_table3_1_terrain_*).
    stage(fmt::format("reading the grid {}", a.terrain));
    const sim::TerrainField field(sim::read_terrain_grid(a.terrain));
    auto& w = a.world;
    for (double* v :
         {&w.reference_size, &w.query_size, &w.track_spacing, &w.sample_spacing, &w.max_translation})
      *v *= a.scale;
    stage(fmt::format("terrain world {} of seed {}", a.index, a.seed));
    const app::TerrainWorldTruth tt = app::write_terrain_world(field, w, a.seed, a.index, a.scale, staging);
    t = tt.truth;
    unit = fmt::format("× {:g} m", a.scale);
    extra = {{"length_unit_m", a.scale},
             {"centre_m", {tt.centre_x, tt.centre_y}},
             {"roughness_m", tt.roughness},
             {"grid", a.terrain}};
  }
  outputs.commit();
  if (a.common.json) {
    json j = {{"dir", a.dir},
              {"seed", a.seed},
              {"index", a.index},
              {"truth", {{"theta", t.theta}, {"tx", t.tx}, {"ty", t.ty}}}};
    j.update(extra);
    fmt::print("{}\n", j.dump(1));
    return;
  }
  fmt::print("truth        p_ref = R(θ) p_query + t, θ = {:.9g} rad, t = ({:.9g}, {:.9g}) {}\n", t.theta,
             t.tx, t.ty, unit);
  if (!a.terrain.empty())
    fmt::print(
        "terrain      reference centred at ({:.1f}, {:.1f}) m on the grid; roughness under the query {:.3g} "
        "m "
        "(elevation RMS about its plane); positions in units of {:g} m\n",
        extra["centre_m"][0].get<double>(), extra["centre_m"][1].get<double>(),
        extra["roughness_m"].get<double>(), a.scale);
  fmt::print("written      {}/{{reference.csv, query.csv, truth.csv}}\n", a.dir);
}

}  // namespace

void add_align_command(CLI::App& app) {
  auto a = std::make_shared<AlignArgs>();
  auto* c = app.add_subcommand(
      "align", "align a query survey to a reference survey without data association (thesis ch. 3)");
  c->group("Your data");
  c->add_option("reference", a->reference, "reference survey CSV: x, y[, depth], feature columns")
      ->required();
  c->add_option("query", a->query, "query survey CSV, the same columns, positions in its own frame")
      ->required();
  c->add_flag("--depth", a->depth, "the third column of both files is depth (the known-depth case, eq. 3.9)");
  c->add_option("--method", a->method, "proposed, so_conv_hull, symmetric or affine (Table 3.1)")
      ->capture_default_str();
  c->add_option(
       "--dissimilarity", a->dissimilarity,
       "standardized (Euclidean after dividing every feature column by its std over the reference) or "
       "euclidean (raw feature vectors)")
      ->capture_default_str();
  auto& o = a->options;
  c->add_option("--rounds", o.region.max_rounds,
                "shrinking rounds after round 0 (0: round 0 only, the whole reference)")
      ->capture_default_str();
  c->add_option("--shrink", o.region.shrink, "box half-width factor per round")->capture_default_str();
  c->add_option("--min-half-width", o.region.min_half_width, "rounds stop below this half-width (m)")
      ->capture_default_str();
  c->add_option("--depth-gate", o.depth_gate, "--depth: pair points whose depths differ by at most this (m)")
      ->capture_default_str();
  c->add_flag("--certify", o.certify,
              "also certify the optimum over SO(2) of round 0's objective (branch and bound over θ)");
  c->add_option("--threads", o.threads, "threads for hulls and sectors (the answer does not depend on it)")
      ->capture_default_str();
  add_common(c, a->common);
  c->callback([a] {
    check_align_options(*a);
    run_align(*a);
  });

  auto w = std::make_shared<WorldArgs>();
  auto& wo = w->world;
  wo.feature_noise = 0.3;  // the generator settings of ch3_table3_1_alignment
  auto* cw = app.add_subcommand(
      "align-world",
      "write a simulated survey pair of Table 3.1's generator (or over a real elevation grid, --terrain) as "
      "the CSV files keel align reads");
  cw->group("Your data");
  cw->add_option("dir", w->dir,
                 "output folder for reference.csv, query.csv, truth.csv (created; files of these names are "
                 "replaced only as the whole set an earlier keel align-world wrote)")
      ->required();
  cw->add_option("--seed", w->seed, "experiment seed (ch3_table3_1_alignment's by default)")
      ->capture_default_str();
  cw->add_option("--index", w->index, "world index: world w of that experiment")->capture_default_str();
  cw->add_option("--feature-noise", wo.feature_noise, "feature noise std (field RMS 1)")
      ->capture_default_str();
  cw->add_option("--query-size", wo.query_size, "query square side (m)")->capture_default_str();
  cw->add_option("--bump-sigma-min", wo.bump_sigma_min, "feature field length scale, low end (m)")
      ->capture_default_str();
  cw->add_option("--bump-sigma-max", wo.bump_sigma_max, "feature field length scale, high end (m)")
      ->capture_default_str();
  cw->add_option("--bumps", wo.bumps, "Gaussian bumps per feature component")->capture_default_str();
  cw->add_option("--terrain", w->terrain,
                 "a keel grid file (datasets/README.md): survey the real terrain instead of the bump field; "
                 "features elevation, slope and curvature (the worlds of ch3_table3_1_terrain_*)");
  cw->add_option("--scale", w->scale,
                 "--terrain: Table 3.1's geometry times this (m per sample spacing; --query-size is then in "
                 "sample spacings), and the written positions in units of it")
      ->capture_default_str();
  add_common(cw, w->common);
  cw->callback([w] {
    check_world_options(*w);
    run_world(*w);
  });
}

}  // namespace keel::cli
