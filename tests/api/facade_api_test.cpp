// Facade-API tests: use the engine exactly as drivers do, through `import` (imports before any include,
// DESIGN rule 4).
import keel.core;
import keel.repro;
import keel.lie;
import keel.pcm;
import keel.sim;
import keel.sos;
import keel.study;

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lie = keel::lie;
namespace core = keel::core;
namespace repro = keel::repro;
namespace pcm = keel::pcm;
namespace sim = keel::sim;
namespace sos = keel::sos;
namespace ch5 = keel::study::ch5;

TEST_CASE("keel.lie facade: group round trip and the adjoint identity (eq. 5.10)") {
  lie::Vec6 xi;
  xi << 0.3, -0.2, 0.1, 0.05, -0.4, 1.2;
  const lie::SE3 T = lie::SE3::exp(xi);
  CHECK((T.log() - xi).norm() < 1e-12);
  lie::Vec6 eta;
  eta << -0.1, 0.2, 0.05, 0.3, 0.1, -0.2;
  const lie::SE3 lhs = T * lie::SE3::exp(eta) * T.inverse();
  const lie::SE3 rhs = lie::SE3::exp(T.adjoint() * eta);
  CHECK(lhs.is_approx(rhs, 1e-10));
}

TEST_CASE(
    "keel.study facade: relative pose of correlated poses beats the independent formula (Fig. 5.6 at alpha = "
    "1)") {
  auto s = ch5::relative_pose_setup(lie::kPi / 4, {3, 3, 0}, {4.5, 4.5, 0},
                                    {0.005, 0.005, 1e-5, 1e-5, 1e-5, 0.006}, {0.0005, 0.0005, 0, 0, 0, 0.005},
                                    1.0);
  s.samples = 20000;
  const auto out = ch5::simulate_relative_pose(s, repro::RunContext(core::Streams(5)));
  CHECK(out.error_joint * 20 < out.error_independent);
  // The joint prediction is within Monte-Carlo noise of the sampled covariance (relative Frobenius error).
  CHECK(out.error_joint / out.cov_mc.norm() < 0.03);
}

TEST_CASE("keel.study facade: composition Monte Carlo is deterministic across thread counts") {
  ch5::CompositionSetup s;
  s.steps = 5;
  s.trajectories = 3000;
  const auto a = ch5::simulate_composition(s, repro::RunContext(core::Streams(11), 1));
  const auto b = ch5::simulate_composition(s, repro::RunContext(core::Streams(11), 2));
  CHECK(a.lie_joint.inside == b.lie_joint.inside);
  CHECK(a.ssc.inside == b.ssc.inside);
  // Bad setups are rejected with the violated constraint named.
  s.rho = 1.0;
  CHECK_THROWS_WITH_AS((void)ch5::simulate_composition(s, repro::RunContext(core::Streams(11))),
                       doctest::Contains("rho"), std::invalid_argument);
}

TEST_CASE(
    "keel.study facade: at small noise every first-order prediction is consistent (Monte-Carlo agreement)") {
  ch5::CompositionSetup s;
  s.steps = 10;
  s.sigma_t = 0.01;
  s.sigma_r = 0.01;
  s.rho = 0.4;
  s.trajectories = 20000;
  s.levels = {0.95, 0.999};
  const auto out = ch5::simulate_composition(s, repro::RunContext(core::Streams(3)));
  const double se = std::sqrt(0.95 * 0.05 / 20000.0);
  // With the correlation modelled, first and fourth order agree with Monte Carlo; SSC too (small noise,
  // near-linear).
  CHECK(std::fabs(out.lie_joint.inside[0] - 0.95) < 4 * se);
  CHECK(std::fabs(out.lie_joint_fourth_order.inside[0] - 0.95) < 4 * se);
  CHECK(std::fabs(out.ssc.inside[0] - 0.95) < 4 * se);
  CHECK(std::fabs(out.lie_joint.inside[1] - 0.999) < 0.002);
  // Ignoring the positive correlation under-covers even at small noise.
  CHECK(out.lie_independent.inside[0] < 0.95 - 10 * se);
  CHECK(out.ssc_independent.inside[0] < 0.95 - 10 * se);
}

TEST_CASE(
    "keel.study facade: the UT conversion of SSC (Fig. 5.7) matches the joint prediction at small noise") {
  ch5::CompositionSetup s;
  s.steps = 10;
  s.sigma_t = 0.01;
  s.sigma_r = 0.01;
  s.rho = 0.4;
  s.trajectories = 20000;
  const repro::RunContext context(core::Streams(5));
  CHECK_THROWS_WITH_AS((void)ch5::convert_ssc_prediction(ch5::simulate_composition(s, context), {0.95}),
                       doctest::Contains("keep_samples"), std::invalid_argument);
  s.keep_samples = true;
  const auto out = ch5::simulate_composition(s, context);
  const auto c = ch5::convert_ssc_prediction(out, {0.95});
  // Near-linear regime: SSC is accurate, so its conversion agrees with the joint Lie-algebra prediction and
  // with the samples' spread (volumes within a few percent, coverage within Monte-Carlo error).
  CHECK(c.volume_vs_joint == doctest::Approx(1.0).epsilon(0.03));
  CHECK(c.volume_vs_samples == doctest::Approx(1.0).epsilon(0.05));
  CHECK(std::fabs(c.unscented.inside[0] - 0.95) < 4 * std::sqrt(0.95 * 0.05 / 20000.0));
  CHECK(c.unscented.mean.translation().isApprox(out.ssc.mean.translation(), 1e-12));
}

TEST_CASE("keel.core facade: config errors name file, table and key") {
  const auto dir = std::filesystem::temp_directory_path() / "keel_api_test" / "demo";
  std::filesystem::create_directories(dir);
  const auto file = dir / "experiment.toml";
  std::ofstream(file)
      << "id = \"demo\"\ntitle = \"t\"\nreproduces = \"r\"\nseed = 1\n[params]\nsteps = \"ten\"\n"
         "[profiles.quick]\n";
  const auto cfg = repro::ExperimentConfig::load(file, "quick");
  CHECK_THROWS_WITH_AS(
      (void)cfg.params.integer("steps"),
      doctest::Contains("experiment.toml: [params] key 'steps' (line 6): expected an integer"),
      core::ConfigError);
  std::filesystem::remove_all(dir.parent_path());
}

TEST_CASE(
    "keel.pcm facade: PCM-Exact equals the combinatorial maximum of eq. 2.5 on 1D worlds; RANSAC does not") {
  sim::World1DOptions options;  // the defaults of world1d.hpp
  const double gamma = pcm::consistency_threshold(0.11, 1);
  int ransac_inconsistent = 0;
  for (std::uint64_t w = 0; w < 200; ++w) {
    const auto world = sim::generate_world1d(options, 4242, w);
    const auto Q = sim::world1d_consistency_matrix(world);
    const auto comb = pcm::max_consistent_set_combinatorial(Q, gamma);
    const auto exact = pcm::select_pcm(Q, gamma, pcm::CliqueAlgorithm::exact);
    CHECK(exact.selected.size() == comb.selected.size());
    CHECK(pcm::count_inconsistent_pairs(Q, exact.selected, gamma) == 0);
    ransac_inconsistent += pcm::count_inconsistent_pairs(Q, pcm::select_ransac(Q, gamma).selected, gamma) > 0;
  }
  CHECK(ransac_inconsistent > 0);  // RANSAC does not enforce pairwise consistency (§2.7.1)
}

TEST_CASE("keel.sos facade: the counterexample is not tight at order 1 and certified at order 2") {
  const auto g = sos::exactness_counterexample();
  sos::CertifyOptions o;
  o.escalate = false;
  const sos::CertifiedSolution first = sos::solve_certified(g, o);
  CHECK(first.status == core::SearchStatus::unproven);
  CHECK(first.bound.lower < first.bound.upper - 0.5);
  o.escalate = true;
  const sos::CertifiedSolution second = sos::solve_certified(g, o);
  CHECK(second.status == core::SearchStatus::optimal);
  CHECK(second.certified_order == 2);
  CHECK(second.bound.upper <= first.bound.upper + 1e-9);  // order 2 may also round to a better solution
  CHECK(core::to_string(second.status) == "optimal");
}
