#include "study/ch4/robust_backend.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "kit/test_kit.hpp"
#include "repro/experiment_config.hpp"

namespace fs = std::filesystem;
using keel::study::ch4::RobustBackend;
using keel::testkit::throws_with;

namespace {

const fs::path kRobustConfig = fs::path(KEEL_SOURCE_DIR) / "experiments/ext_robust_backend/experiment.toml";

// The committed config with one line of [params] replaced (`from` must occur once).
RobustBackend::Options read_robust_with(const std::string& from, const std::string& to) {
  std::ifstream in(kRobustConfig);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  const fs::path dir = fs::temp_directory_path() / "keel_robust_backend_test" / "ext_robust_backend";
  fs::create_directories(dir);
  const fs::path file = dir / "experiment.toml";
  std::ofstream(file) << text;
  return RobustBackend::Options::read(keel::repro::ExperimentConfig::load(file, "full").params);
}

}  // namespace

TEST_CASE("ext_robust_backend's grid: the issue's cells, each key once, at least 20 trials in full") {
  const auto full =
      RobustBackend::Options::read(keel::repro::ExperimentConfig::load(kRobustConfig, "full").params);
  const auto cells = RobustBackend::make_cells(full);
  // Per graph and robot count: the outlier-free cell, then each kind at each rate above 0.
  const std::size_t per = 1 + full.kinds.size() * (full.rates.size() - 1);
  CHECK(cells.size() == full.graphs.size() * full.robots.size() * per);
  std::set<std::string> keys;
  for (const auto& c : cells) keys.insert(c.key.name());
  CHECK(keys.size() == cells.size());
  CHECK(keys.count("intel.r2.aliased.out40") == 1);
  CHECK(keys.count("intel.r4.clean") == 1);
  CHECK(full.trials >= 20);
  CHECK(full.robust.threads == 1);
  CHECK(full.robust.solve.time_limit_s > 0);
}

TEST_CASE("ext_robust_backend's config: bad values are refused, naming the key") {
  CHECK(throws_with<std::exception>(
      [] { (void)read_robust_with("kinds = [\"random\"", "kinds = [\"clustered\""); }, "kinds"));
  CHECK(
      throws_with<std::exception>([] { (void)read_robust_with("rates = [0.0,", "rates = [1.0,"); }, "rates"));
  CHECK(
      throws_with<std::exception>([] { (void)read_robust_with("robots = [1,", "robots = [0,"); }, "robots"));
  CHECK(throws_with<std::exception>([] { (void)read_robust_with("p = 0.11", "p = 1.5"); },
                                    "p must be in (0, 1)"));
}

TEST_CASE(
    "ext_robust_backend's residual test: keel robust's defaults as re-registered; absent keys, the first "
    "registration") {
  const auto full =
      RobustBackend::Options::read(keel::repro::ExperimentConfig::load(kRobustConfig, "full").params);
  CHECK(full.robust.residual_test == keel::merge::RobustResidualTest::groups);
  CHECK(full.robust.group_window == 5);
  CHECK(full.robust.first_solve_rank_d);
  // The keys the re-registration added, as a config names them; without them, the pipeline first registered:
  // the edge χ² test from the certified solve.
  const std::string keys = "residual_test = \"groups\"\ngroup_window = 5\nfirst_solve = \"rank-d\"";
  const auto first = read_robust_with(keys, "");
  CHECK(first.robust.residual_test == keel::merge::RobustResidualTest::edge);
  CHECK_FALSE(first.robust.first_solve_rank_d);
  const auto groups = read_robust_with(keys, "residual_test = \"groups\"\ngroup_window = 3");
  CHECK(groups.robust.residual_test == keel::merge::RobustResidualTest::groups);
  CHECK(groups.robust.group_window == 3);
  CHECK(read_robust_with(keys, "first_solve = \"rank-d\"").robust.first_solve_rank_d);
  CHECK(throws_with<std::exception>([&] { (void)read_robust_with(keys, "first_solve = \"rank-3\""); },
                                    "first_solve"));
  CHECK(throws_with<std::exception>([&] { (void)read_robust_with(keys, "residual_test = \"chi\""); },
                                    "residual_test"));
  CHECK(
      throws_with<std::exception>([&] { (void)read_robust_with(keys, "group_window = 0"); }, "group_window"));
}
