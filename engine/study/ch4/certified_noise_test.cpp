#include "study/ch4/certified_noise.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "kit/test_kit.hpp"
#include "repro/experiment_config.hpp"

namespace fs = std::filesystem;
using keel::study::ch4::CertifiedNoiseSweep;
using keel::testkit::throws_with;

namespace {

const fs::path kConfig = fs::path(KEEL_SOURCE_DIR) / "experiments/ext_certified_noise/experiment.toml";

// The committed config with one line of [params] replaced (`from` must occur once).
CertifiedNoiseSweep::Options read_with(const std::string& from, const std::string& to) {
  std::ifstream in(kConfig);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
  // The loader wants the id's folder name.
  const fs::path dir = fs::temp_directory_path() / "keel_certified_noise_test" / "ext_certified_noise";
  fs::create_directories(dir);
  const fs::path file = dir / "experiment.toml";
  std::ofstream(file) << text;
  const auto config = keel::repro::ExperimentConfig::load(file, "full");
  return CertifiedNoiseSweep::Options::read(config.params);
}

}  // namespace

TEST_CASE(
    "ext_certified_noise's config: six levels named by value, ten graphs per level in the full profile") {
  const auto full =
      CertifiedNoiseSweep::Options::read(keel::repro::ExperimentConfig::load(kConfig, "full").params);
  REQUIRE(full.levels.size() == 6);
  const char* names[] = {"rot0p1", "rot0p3", "rot1", "rot2", "out10", "out30"};
  for (std::size_t l = 0; l < 6; ++l) CHECK(full.levels[l].name == names[l]);
  CHECK(full.levels[3].rotation_noise == 2.0);
  CHECK(full.levels[3].outlier_fraction == 0.0);
  CHECK(full.levels[5].outlier_fraction == 0.3);
  CHECK(full.levels[5].rotation_noise == 0.0);
  CHECK(full.subsets.size() * static_cast<std::size_t>(full.draws) >= 10);
  CHECK(full.solve.time_limit_s > 0);
  const auto quick =
      CertifiedNoiseSweep::Options::read(keel::repro::ExperimentConfig::load(kConfig, "quick").params);
  CHECK(quick.levels.size() == 3);
  CHECK(quick.draws == 1);
}

TEST_CASE("ext_certified_noise's config: bad values are refused, naming the key") {
  CHECK(throws_with<std::exception>([] { (void)read_with("draws = 2 ", "draws = 0 "); }, "draws"));
  CHECK(throws_with<std::exception>(
      [] { (void)read_with("rotation_noise = [0.1,", "rotation_noise = [-0.1,"); }, "rotation_noise = -0.1"));
  CHECK(throws_with<std::exception>(
      [] { (void)read_with("outlier_fraction = [0.1,", "outlier_fraction = [1.1,"); },
      "outlier_fraction = 1.1"));
  CHECK(throws_with<std::exception>(
      [] { (void)read_with("dimension = 2, poses = 500 }\nintel", "dimension = 2, poses = -5 }\nintel"); },
      "poses"));
  CHECK(throws_with<std::exception>(
      [] { (void)read_with("datasets = [\"manhattan\",", "datasets = [\"manhatan\","); }, "graphs.manhatan"));
  CHECK(throws_with<std::exception>([] { (void)read_with("time_limit_s = 60.0", "time_limit_s = -1.0"); },
                                    "time_limit"));
}
