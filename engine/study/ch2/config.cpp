#include "study/ch2/config.hpp"

#include <fmt/format.h>

#include <type_traits>
#include <variant>

#include <stdexcept>
#include <tuple>

#include "datasets/manifest.hpp"
#include "graph/trajectory.hpp"
#include "graph/io.hpp"

namespace keel::study::ch2 {

namespace {

int read_int(const core::ConfigTable& t, std::string_view key) { return static_cast<int>(t.integer(key)); }

}  // namespace

std::pair<double, double> read_range(const core::ConfigTable& t, std::string_view key) {
  const auto v = t.numbers(key);
  if (v.size() != 2) throw core::ConfigError(fmt::format("{}: expected [min, max]", t.where(key)));
  return {v[0], v[1]};
}

sim::SplitOptions read_split(const core::ConfigTable& t) {
  sim::SplitOptions split;
  split.first = read_int(t, "first");
  split.split = read_int(t, "split");
  split.last = read_int(t, "last");
  return split;
}

sim::CandidateOptions read_candidate_options(const core::ConfigTable& t) {
  sim::CandidateOptions c;
  c.num_inliers = read_int(t, "num_inliers");
  c.aliased_groups = read_int(t, "aliased_groups");
  c.aliased_group_size = read_int(t, "aliased_group_size");
  c.random_outliers = read_int(t, "random_outliers");
  std::tie(c.random_sigma_translation_min, c.random_sigma_translation_max) =
      read_range(t, "random_sigma_translation");
  std::tie(c.random_sigma_rotation_min, c.random_sigma_rotation_max) = read_range(t, "random_sigma_rotation");
  // Optional near-miss aliased groups (sim::CandidateOptions): both ranges or neither.
  if (t.has("near_miss_translation") || t.has("near_miss_rotation")) {
    std::tie(c.near_miss_translation_min, c.near_miss_translation_max) =
        read_range(t, "near_miss_translation");
    std::tie(c.near_miss_rotation_min, c.near_miss_rotation_max) = read_range(t, "near_miss_rotation");
  }
  t.validate(c);
  return c;
}

std::vector<StudyMethod> read_methods(const core::ConfigTable& p) {
  std::vector<StudyMethod> out;
  const auto table = p.table("method");
  for (const auto& name : p.strings("methods")) {
    if (!table.has(name))
      throw core::ConfigError(fmt::format("{}: no [params.method.{}] table", p.where("methods"), name));
    const auto t = table.table(name);
    StudyMethod m;
    m.method.name = name;
    m.label = t.string("label");
    const auto kind = t.parse("kind", merge::merge_method_kind_from_string);
    m.method = merge::MergeMethod::make(name, kind);
    // Only the keys of the method's kind are read: a key of another kind is an unknown key.
    std::visit(
        [&](auto& o) {
          using O = std::decay_t<decltype(o)>;
          if constexpr (requires { o.p; }) o.p = t.number_or("p", o.p);
          if constexpr (requires { o.composition; })
            o.composition = t.parse_or("composition", pcm::composition_from_string, o.composition);
          if constexpr (std::is_same_v<O, merge::Dcs>) {
            o.phi = t.number_or("dcs_phi", o.phi);
            o.accept_scale = t.number_or("dcs_accept_scale", o.accept_scale);
          } else if constexpr (std::is_same_v<O, merge::Scgp>) {
            o.options.affinity_scale = t.number_or("scgp_affinity_scale", o.options.affinity_scale);
            o.options.discretization = t.parse_or("scgp_discretization", pcm::scgp_discretization_from_string,
                                                  o.options.discretization);
          } else if constexpr (std::is_same_v<O, merge::Densest>) {
            o.options.affinity_scale = t.number_or("densest_affinity_scale", o.options.affinity_scale);
          }
        },
        m.method.options);
    t.validate(m.method);
    out.push_back(m);
  }
  return out;
}

pcm::ScgpOptions read_scgp_options(const core::ConfigTable& t) {
  pcm::ScgpOptions o;
  o.affinity_scale = t.number("scgp_affinity_scale");
  o.discretization = t.parse("scgp_discretization", pcm::scgp_discretization_from_string);
  o.min_eigen_ratio = t.number("scgp_min_eigen_ratio");
  t.validate(o);
  return o;
}

sim::World1DOptions read_world1d_options(const core::ConfigTable& t, bool with_counts) {
  sim::World1DOptions w;
  w.x = t.number("x");
  w.sigma_inlier = t.number("sigma_inlier");
  if (with_counts) {
    w.inliers_min = read_int(t, "inliers_min");
    w.inliers_max = read_int(t, "inliers_max");
    w.aliased_min = read_int(t, "aliased_min");
    w.aliased_max = read_int(t, "aliased_max");
    w.random_min = read_int(t, "random_min");
    w.random_max = read_int(t, "random_max");
  }
  w.outlier_mean_range = t.number("outlier_mean_range");
  w.outlier_sigma_min = t.number("outlier_sigma_min");
  w.outlier_sigma_max = t.number("outlier_sigma_max");
  if (with_counts) t.validate(w);
  return w;
}

MeasurementRegime read_regime(const core::ConfigTable& t, std::string name) {
  MeasurementRegime g;
  g.name = std::move(name);
  g.label = t.string_or("label", "");
  const std::string measurements = t.string("measurements");
  if (measurements == "resampled") {
    g.resampled = true;
    g.noise_scale = t.number("noise_scale");
    const auto seed = t.integer("resample_seed");
    if (seed < 0) throw core::ConfigError(fmt::format("{}: must be >= 0", t.where("resample_seed")));
    g.resample_seed = static_cast<std::uint64_t>(seed);
  } else if (measurements != "dataset") {
    throw core::ConfigError(
        fmt::format("{}: expected \"dataset\" or \"resampled\"", t.where("measurements")));
  }
  t.validate(g);
  return g;
}

std::vector<MeasurementRegime> read_regimes(const core::ConfigTable& p, std::string_view list_key,
                                            std::string_view table_key) {
  std::vector<MeasurementRegime> out;
  const auto table = p.table(table_key);
  for (const auto& name : p.strings(list_key)) {
    if (!table.has(name))
      throw core::ConfigError(fmt::format("{}: no [params.{}.{}] table", p.where(list_key), table_key, name));
    out.push_back(read_regime(table.table(name), name));
  }
  return out;
}

ScenarioFiles ScenarioFiles::read(const core::ConfigTable& t) {
  ScenarioFiles f;
  f.dataset = t.string("dataset");
  f.graph_file = t.string("graph_file");
  f.ground_truth_file = t.string("ground_truth_file");
  f.split = read_split(t);
  return f;
}

sim::TwoRobotScenario2 load_scenario_2d(const ScenarioFiles& f) {
  const auto graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(f.dataset, f.graph_file));
  const auto truth = graph::read_poses_2d(datasets::resolve_dataset_file(f.dataset, f.ground_truth_file));
  return sim::split_two_robots(graph, truth, f.split);
}

sim::TwoRobotScenario3 load_scenario_3d(const ScenarioFiles& f) {
  const auto graph = graph::read_pose_graph_3d(datasets::resolve_dataset_file(f.dataset, f.graph_file));
  const auto truth = graph::read_poses_3d(datasets::resolve_dataset_file(f.dataset, f.ground_truth_file));
  return sim::split_two_robots(graph, truth, f.split);
}

}  // namespace keel::study::ch2
