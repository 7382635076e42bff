// Unit tests of the chapter-4 studies and config readers: a segment study on noise-free synthetic data, the
// exactness study's bookkeeping, and config errors located at file, table and key.
#include <doctest/doctest.h>

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
  const ExactnessOutcome out = run_exactness_study(o, RunContext(Streams(0)));
  REQUIRE(out.trials.size() == 1);
  REQUIRE(out.trials[0].size() == 4);
  for (const auto& t : out.trials[0]) CHECK(t.certified);
  o.families[0].poses = 1;
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [&] { (void)run_exactness_study(o, RunContext(Streams(0))); }, "poses >= 2"));
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
