// Unit tests of the chapter-4 studies and config readers: a segment study on noise-free synthetic data, the
// exactness study's bookkeeping, and config errors located at file, table and key.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/config.hpp"
#include "core/random.hpp"
#include "kit/test_kit.hpp"
#include "study/ch4/segments.hpp"

using namespace keel::sos;
using namespace keel::study::ch4;
using keel::core::Rng;
using keel::core::Streams;
using keel::lie::SE2;
using keel::repro::RunContext;

namespace {
// A noise-free chain with loop closures every 7 poses.
keel::graph::PoseGraph2D chain(int n, std::vector<SE2>& truth) {
  Rng rng(3);
  truth = {SE2::identity()};
  for (int i = 1; i < n; ++i) truth.push_back(truth.back() * SE2(1.0, 0.0, rng.uniform(-0.5, 0.5)));
  keel::graph::PoseGraph2D g;
  auto edge = [&](int i, int j) {
    keel::graph::Edge2 e;
    e.i = i, e.j = j;
    e.measurement = truth[static_cast<std::size_t>(i)].inverse() * truth[static_cast<std::size_t>(j)];
    e.information = keel::lie::Mat3(Eigen::Vector3d(10, 10, 20).asDiagonal());
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  for (int i = 0; i + 7 < n; i += 7) edge(i, i + 7);
  g.poses = truth;
  return g;
}
}  // namespace

TEST_CASE("segment study on noise-free data: every segment certified, SBSOS and LM from odometry exact") {
  std::vector<SE2> truth;
  const auto g = chain(36, truth);
  SegmentStudyOptions o;
  o.segment_length = 12, o.stride = 12;
  const SegmentStudyOutcome out = run_segment_study(g, truth, {}, o, RunContext(Streams(0), 2));
  REQUIRE(out.segments.size() == 3);
  for (const auto& s : out.segments) {
    CHECK(!s.failed);
    CHECK(s.status == keel::core::SearchStatus::optimal);
    CHECK(s.sbsos.trans_error < 1e-6);
    CHECK(s.sbsos.rot_error < 1e-6);
    CHECK(s.lm_odometry.trans_error < 1e-6);
    CHECK(s.sbsos.cost < 1e-8);
    CHECK(s.lm_random.cost >= s.sbsos.cost - 1e-9);  // nothing beats the certified minimum
  }
  CHECK(out.segments[1].first == 12);
}

TEST_CASE("segment study: bad options and data give clear errors") {
  std::vector<SE2> truth;
  const auto g = chain(20, truth);
  SegmentStudyOptions o;
  o.segment_length = 30;
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_segment_study(g, truth, {}, o, RunContext(Streams(0))); },
      "no segment of 30 poses fits"));
  o.segment_length = 1;
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_segment_study(g, truth, {}, o, RunContext(Streams(0))); },
      "segment_length must be >= 2"));
  o.segment_length = 10;
  truth.pop_back();
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_segment_study(g, truth, {}, o, RunContext(Streams(0))); }, "ground-truth poses"));
}

TEST_CASE("exactness study: trials are certified and counted per family") {
  ExactnessOptions o;
  ExactnessFamily f;
  f.name = "n4", f.poses = 4, f.rotation_noise = 0.2, f.trials = 4;
  o.families = {f};
  o.multistart_starts = 10;
  const ExactnessOutcome out = run_exactness_study(o, RunContext(Streams(0)));
  REQUIRE(out.trials.size() == 1);
  REQUIRE(out.trials[0].size() == 4);
  for (const auto& t : out.trials[0]) {
    // Nearly consistent rotations: order 1 is tight, its rounding finds the minimum, the multistart finds the
    // same minimum from every start, and the dual certificate proves it.
    CHECK(t.certified);
    CHECK(t.certified_order1);
    CHECK(t.tight_order1);
    CHECK(t.dual_certified);
    CHECK(t.multistart == doctest::Approx(t.upper).epsilon(1e-8));
    CHECK(t.multistart_hits == 10);
    CHECK(t.lower_order1 <= t.best * (1 + 1e-9));
  }
  o.families[0].poses = 1;
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_exactness_study(o, RunContext(Streams(0))); }, "poses >= 2"));
  o.families[0].poses = 4;
  o.multistart_starts = 0;
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_exactness_study(o, RunContext(Streams(0))); }, "multistart_starts must be >= 1"));
}

TEST_CASE("exactness study: where order 1 is not tight, multistart and order 2 find the same minimum") {
  // Rotations drawn uniformly on K5: order 1 leaves some trials open (its bound below every minimum found);
  // escalation certifies them at order 2, and the multistart (Newton on f from random angles, independent of
  // both relaxations) must reach the certified minimum and never go below a lower bound.
  ExactnessOptions o;
  ExactnessFamily f;
  f.name = "k5", f.poses = 5, f.uniform_rotations = true, f.rotation_noise = 0, f.translation_noise = 0;
  f.extent = 0, f.trials = 24;
  o.families = {f};
  o.multistart_starts = 30;
  o.certify.escalation_max_moments = 6000;
  const ExactnessOutcome out = run_exactness_study(o, RunContext(Streams(3)));
  int open = 0;
  for (const auto& t : out.trials[0]) {
    CHECK(t.multistart >= t.lower_order1 - 1e-6 * std::max(t.best, 1.0));
    if (std::isfinite(t.lower_dual)) CHECK(t.multistart >= t.lower_dual - 1e-6 * std::max(t.best, 1.0));
    if (t.certified_order1) CHECK(t.tight_order1);
    if (t.dual_certified) CHECK(t.tight_order1);
    if (t.tight_order1) continue;
    ++open;
    CHECK(t.gap_order1 > 1e-6);
    REQUIRE(t.escalated);
    CHECK(t.certified);
    CHECK(t.lower_order2 <= t.best + 1e-6 * std::max(t.best, 1.0));
    CHECK(t.multistart == doctest::Approx(t.upper).epsilon(1e-6));
  }
  CHECK(open > 0);  // the draw contains graphs where order 1 is not exact
}

TEST_CASE("exactness options: the noise map expands into one family per cell, errors located") {
  const auto dir = std::filesystem::temp_directory_path() / "keel_exactness_config_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "experiment.toml";
  const std::string common =
      "[params]\nstructure = \"dense\"\nsolver = \"dsdp\"\nsdp_gap_tolerance = 1e-9\ngap_tolerance = 1e-6\n"
      "escalate = true\nescalation_max_moments = 10\npolish_max_iterations = 5\nmultistart_starts = 3\n"
      "multistart_gradient_tolerance = 1e-12\nmultistart_max_iterations = 50\ndual_bound_factorizations = 2\n"
      "trials = 2\nfamilies = [\"a\"]\n[params.family.a]\nposes = 4\nedge_probability = 1.0\n"
      "rotation_noise = 0.1\ntranslation_noise = 0.1\nextent = 3.0\nescalate = false\n"
      "[params.noise_map]\nrotation_noise = [0.1, 1.5]\nedge_probability = 1.0\ntranslation_noise = 0.1\n"
      "extent = 3.0\n";
  std::ofstream(file) << common << "poses = [4, 10]\n";
  {
    const auto cfg = keel::core::load_toml(file);
    const ExactnessOptions o = read_exactness_options(cfg.table("params"), "family");
    REQUIRE(o.families.size() == 5);
    CHECK_FALSE(o.families[0].escalate);
    CHECK_FALSE(o.families[0].noise_map);
    CHECK(o.families[1].name == "map_k4_s0100");
    CHECK(o.families[4].name == "map_k10_s1500");
    CHECK(o.families[4].poses == 10);
    CHECK(o.families[4].rotation_noise == 1.5);
    CHECK(o.families[4].noise_map);
    CHECK_FALSE(o.families[4].escalate);
    CHECK(o.families[4].trials == 2);
    CHECK(o.multistart_starts == 3);
    CHECK(o.dual.bound_factorizations == 2);
  }
  std::ofstream(file) << common << "poses = [4.5]\n";
  const auto cfg = keel::core::load_toml(file);
  const std::string msg = [&] {
    try {
      (void)read_exactness_options(cfg.table("params"), "family");
    } catch (const keel::core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("<no throw>");
  }();
  CHECK(keel::testkit::contains(msg, "[params.noise_map] key 'poses'"));
  CHECK(keel::testkit::contains(msg, "poses must be integers"));
}

TEST_CASE("config readers locate a bad value at its key") {
  const auto dir = std::filesystem::temp_directory_path() / "keel_sos_config_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "experiment.toml";
  std::ofstream(file) << "[params]\nstructure = \"sparse\"\nsolver = \"dsdp\"\nsdp_gap_tolerance = 1e-9\n"
                         "gap_tolerance = 1e-6\nescalate = true\nescalation_max_moments = 10\n"
                         "polish_max_iterations = 5\n";
  const auto cfg = keel::core::load_toml(file);
  const std::string msg = [&] {
    try {
      (void)read_certify_options(cfg.table("params"));
    } catch (const keel::core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("<no throw>");
  }();
  CHECK(keel::testkit::contains(msg, "structure"));
  CHECK(keel::testkit::contains(msg, "unknown sos::Structure 'sparse' (valid: dense, cliques)"));
}
