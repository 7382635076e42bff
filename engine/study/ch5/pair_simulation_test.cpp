#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "kit/test_kit.hpp"
#include "lie/euler.hpp"
#include "core/config.hpp"
#include "study/ch5/pair_sample_size.hpp"
#include "study/ch5/pair_simulation.hpp"

using namespace keel::lie;
using namespace keel::study::ch5;
using keel::core::Streams;
using keel::repro::RunContext;
namespace testkit = keel::testkit;

TEST_CASE("pair study: joint prediction agrees with Monte Carlo, independent does not, deterministic" *
          doctest::test_suite("monte_carlo")) {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(10, 5, 1.0), SE2(-4, 8, -2.0)};
  // Strongly correlated pair covariance (like poses far apart along a chain with a common drift).
  Mat6 S = Mat6::Zero();
  const Vec3 sd(0.05, 0.04, 0.01);
  for (int a = 0; a < 3; ++a) {
    S(a, a) = S(a + 3, a + 3) = sd(a) * sd(a);
    S(a, a + 3) = S(a + 3, a) = 0.9 * sd(a) * sd(a);
  }
  PairStudySetup setup;
  setup.samples = 20000;
  const std::vector<std::pair<int, int>> pairs = {{1, 2}, {0, 1}};
  const auto a = simulate_pairs_2d(poses, pairs, {S, S}, setup, RunContext(Streams(7), 1));
  const auto b = simulate_pairs_2d(poses, pairs, {S, S}, setup, RunContext(Streams(7), 2));
  REQUIRE(a.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(a[k].error_joint == b[k].error_joint);
    CHECK(a[k].normalized_error_ssc == b[k].normalized_error_ssc);
    CHECK(a[k].corr_x == doctest::Approx(0.9));
    CHECK(a[k].corr_theta == doctest::Approx(0.9));
    // Small noise: the joint first-order prediction is within Monte-Carlo error (normalized ε ~ sqrt(2/M)),
    // ignoring the 0.9 correlation is off by a large factor.
    CHECK(a[k].normalized_error_lie < 0.05);
    CHECK(a[k].error_independent > 10 * a[k].error_joint);
    // SSC at small noise is first-order accurate too in its own parameters.
    CHECK(a[k].normalized_error_ssc < 0.05);
  }
  CHECK(a[0].i == 1);
  CHECK(a[0].j == 2);
}

TEST_CASE("pair study: bad inputs are rejected with clear messages") {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(1, 0, 0)};
  PairStudySetup setup;
  setup.samples = 10;
  CHECK_THROWS_WITH_AS(
      (void)simulate_pairs_2d(poses, {{0, 5}}, {Mat6::Identity()}, setup, RunContext(Streams(1))),
      doctest::Contains("outside [0, 2)"), std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {}, setup, RunContext(Streams(1))),
                       doctest::Contains("1 pairs but 0"), std::invalid_argument);
  Mat6 bad = Mat6::Identity();
  bad(0, 0) = -1;
  CHECK_THROWS_WITH_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {bad}, setup, RunContext(Streams(1))),
                       doctest::Contains("pair (0, 1)"), std::runtime_error);
  setup.samples = 1;
  CHECK_THROWS_AS((void)simulate_pairs_2d(poses, {{0, 1}}, {Mat6::Identity()}, setup, RunContext(Streams(1))),
                  std::invalid_argument);
}

TEST_CASE(
    "pair study at several sample sizes in one pass: each record bit for bit a run at that size alone") {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(10, 5, 1.0), SE2(-4, 8, -2.0), SE2(3, -2, 3.0)};
  Mat6 S = Mat6::Zero();
  const Vec3 sd(0.3, 0.2, 0.4);  // large enough that θ wraps in some samples
  for (int a = 0; a < 3; ++a) {
    S(a, a) = S(a + 3, a + 3) = sd(a) * sd(a);
    S(a, a + 3) = S(a + 3, a) = 0.5 * sd(a) * sd(a);
  }
  const std::vector<std::pair<int, int>> pairs = {{1, 2}, {0, 1}, {3, 1}};
  const std::vector<std::size_t> sizes = {2, 3, 50, 401};
  const auto all = simulate_pairs_2d_sizes(poses, pairs, {S, S, S}, sizes, RunContext(Streams(11), 2));
  REQUIRE(all.size() == sizes.size());
  auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  for (std::size_t s = 0; s < sizes.size(); ++s) {
    PairStudySetup setup;
    setup.samples = sizes[s];
    const auto alone = simulate_pairs_2d(poses, pairs, {S, S, S}, setup, RunContext(Streams(11), 1));
    REQUIRE(all[s].size() == pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const PairRecord &a = all[s][k], &b = alone[k];
      CHECK(a.i == b.i);
      CHECK(a.j == b.j);
      for (double PairRecord::* f :
           {&PairRecord::corr_x, &PairRecord::corr_y, &PairRecord::corr_theta, &PairRecord::error_joint,
            &PairRecord::error_independent, &PairRecord::normalized_error_lie,
            &PairRecord::normalized_error_ssc, &PairRecord::normalized_error_ssc_raw_angles,
            &PairRecord::normalized_mc_floor})
        CHECK(bits(a.*f) == bits(b.*f));
    }
  }
  // The sizes see different samples: the estimates move between them.
  CHECK(all[2][0].error_joint != all[3][0].error_joint);
}

TEST_CASE("pair study at several sample sizes: sizes must be >= 2 and ascending") {
  std::vector<SE2> poses = {SE2(0, 0, 0), SE2(1, 0, 0)};
  const std::vector<Mat6> covs = {Mat6::Identity()};
  for (const std::vector<std::size_t>& bad :
       {std::vector<std::size_t>{}, {1, 10}, {10, 10}, {20, 10}, {5, 50, 40}})
    CHECK_THROWS_AS((void)simulate_pairs_2d_sizes(poses, {{0, 1}}, covs, bad, RunContext(Streams(1))),
                    std::invalid_argument);
  CHECK_THROWS_WITH_AS((void)simulate_pairs_2d_sizes(poses, {{0, 1}}, covs, {30, 20}, RunContext(Streams(1))),
                       doctest::Contains("ascending (got 20 after 30)"), std::invalid_argument);
}

TEST_CASE("pair sample-size study: its sample sizes must be whole, >= 2 and ascending, the key named") {
  const auto dir = std::filesystem::temp_directory_path() / "keel_pair_sample_size_test";
  std::filesystem::create_directories(dir);
  const auto refused = [&](const std::string& samples) {
    const auto file = dir / "experiment.toml";
    std::ofstream(file) << "[params]\ndataset = \"manhattan3500\"\nfile = \"isam/manhattanOlson3500.txt\"\n"
                           "initial_guess = \"odometry\"\noffsets = [5]\nfigure_offsets = [5]\n"
                           "match_cov_error_joint = 0.1\nmatch_norm_cov_error_lie = 0.1\npair_stride = 25\n"
                           "samples = "
                        << samples << "\n";
    try {
      (void)PairSampleSize::Options::read(keel::core::load_toml(file).table("params"));
    } catch (const keel::core::ConfigError& e) {
      const std::string what = e.what();
      CHECK_MESSAGE(what.find("samples") != std::string::npos, what);
      return true;
    }
    return false;
  };
  CHECK(refused("[500]"));
  CHECK(refused("[1000, 500]"));
  CHECK(refused("[500, 500]"));
  CHECK(refused("[500.5, 1000]"));
  CHECK(refused("[1, 1000]"));
  CHECK_FALSE(refused("[250, 500, 1000]"));
  std::filesystem::remove_all(dir);
}
