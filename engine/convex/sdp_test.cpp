// The SDP form of convex/sdp.hpp on programs with known optima, solved by DSDP and by SDPA: the smallest
// eigenvalue as an SDP, the smallest cost as an LP over the orthant (and the same LP as 1 × 1 blocks), a
// program with both; every optimality measure recomputed by check_sdp; bad programs give clear errors.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>
#include <future>
#include <optional>
#include <thread>
#include <vector>

#include "convex/sdp.hpp"
#include "core/blas.hpp"
#include "core/parallel.hpp"
#include "kit/test_kit.hpp"

using namespace keel::convex;
using keel::testkit::message_of;

namespace {

// min ⟨C, X⟩ s.t. tr X = 1, X ⪰ 0: the optimum is λ_min(C) (dual: max y s.t. C − y I ⪰ 0).
Sdp smallest_eigenvalue(const Eigen::Matrix3d& C) {
  Sdp p;
  p.block_sizes = {3};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c)
      if (C(r, c) != 0.0) p.c.push_back({0, r, c, C(r, c)});
  p.a = {{{0, 0, 0, 1.0}, {0, 1, 1, 1.0}, {0, 2, 2, 1.0}}};
  p.b = {1.0};
  return p;
}

// min cᵀx s.t. Σ x = 1, x ≥ 0: the optimum is min_i c_i, on the orthant.
Sdp smallest_cost(const std::vector<double>& cost) {
  Sdp p;
  p.lp_size = static_cast<int>(cost.size());
  for (int r = 0; r < p.lp_size; ++r) p.lp_c.push_back({r, cost[static_cast<std::size_t>(r)]});
  p.a = {{}};
  p.b = {1.0};
  p.lp_a = {{}};
  for (int r = 0; r < p.lp_size; ++r) p.lp_a[0].push_back({r, 1.0});
  return p;
}

void check_optimal(const Sdp& p, SdpSolver solver, double expected) {
  SdpSettings s;
  s.solver = solver;
  const SdpSolution sol = solve_sdp(p, s);
  const SdpCheck chk = check_sdp(p, sol);
  INFO("solver " << to_string(solver) << ": primal " << chk.primal_objective << ", dual "
                 << chk.dual_objective << ", status " << sol.status);
  CHECK(chk.primal_objective == doctest::Approx(expected).epsilon(1e-6));
  CHECK(chk.dual_objective == doctest::Approx(expected).epsilon(1e-6));
  CHECK(chk.relative_gap < 1e-6);
  CHECK(chk.primal_residual < 1e-6);
  CHECK(chk.x_min_eigenvalue > -1e-7);
  CHECK(chk.s_min_eigenvalue > -1e-7);
  // The solver's own dual objective is bᵀy of the iterate it returned.
  CHECK(sol.solver_dual_objective == doctest::Approx(chk.dual_objective).epsilon(1e-7));
}

}  // namespace

TEST_CASE("the smallest eigenvalue as an SDP, by DSDP and by SDPA") {
  Eigen::Matrix3d C;
  C << 2, 1, 0, 1, 3, 1, 0, 1, 4;
  const double lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues()(0);
  for (SdpSolver solver : {SdpSolver::dsdp, SdpSolver::sdpa})
    check_optimal(smallest_eigenvalue(C), solver, lambda);
}

TEST_CASE("the orthant: an LP by DSDP's LP cone and SDPA's LP block equals the same LP as 1 x 1 blocks") {
  const std::vector<double> cost = {3.0, 1.5, 2.0, 4.0};
  for (SdpSolver solver : {SdpSolver::dsdp, SdpSolver::sdpa}) check_optimal(smallest_cost(cost), solver, 1.5);
  // The same program with each x_r a 1 × 1 PSD block.
  Sdp blocks;
  blocks.a = {{}};
  blocks.b = {1.0};
  for (int r = 0; r < 4; ++r) {
    blocks.block_sizes.push_back(1);
    blocks.c.push_back({r, 0, 0, cost[static_cast<std::size_t>(r)]});
    blocks.a[0].push_back({r, 0, 0, 1.0});
  }
  for (SdpSolver solver : {SdpSolver::dsdp, SdpSolver::sdpa}) check_optimal(blocks, solver, 1.5);
}

TEST_CASE("a PSD block and an orthant together: DSDP and SDPA agree") {
  // min ⟨C, X⟩ + cᵀx  s.t.  tr X + Σ x = 1: the smaller of λ_min(C) and min c.
  Eigen::Matrix3d C;
  C << 2, 1, 0, 1, 3, 1, 0, 1, 4;
  Sdp p = smallest_eigenvalue(C);
  p.lp_size = 2;
  p.lp_c = {{0, 5.0}, {1, 0.9}};
  p.lp_a = {{{0, 1.0}, {1, 1.0}}};
  for (SdpSolver solver : {SdpSolver::dsdp, SdpSolver::sdpa}) check_optimal(p, solver, 0.9);
  p.lp_c = {{0, 5.0}, {1, 7.0}};
  const double lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvalues()(0);
  for (SdpSolver solver : {SdpSolver::dsdp, SdpSolver::sdpa}) check_optimal(p, solver, lambda);
}

TEST_CASE("bad programs and settings give clear errors") {
  Sdp p = smallest_eigenvalue(Eigen::Matrix3d::Identity());
  p.c.push_back({0, 0, 1, 1.0});  // upper triangle
  CHECK(message_of([&] { p.validate(); }).find("is not in the lower triangle of block 0") !=
        std::string::npos);
  p = smallest_eigenvalue(Eigen::Matrix3d::Identity());
  p.b.push_back(0.0);
  CHECK(message_of([&] { p.validate(); }).find("1 constraint matrices but 2 right-hand sides") !=
        std::string::npos);
  p = smallest_cost({1.0, 2.0});
  p.lp_a[0].push_back({2, 1.0});
  CHECK(message_of([&] { p.validate(); }).find("names row 2 of an orthant of size 2") != std::string::npos);
  p = smallest_cost({1.0, 2.0});
  p.lp_a.push_back({});
  CHECK(message_of([&] { p.validate(); }).find("2 orthant rows a_lp but 1 constraints") != std::string::npos);
  Sdp empty;
  CHECK(message_of([&] { empty.validate(); }).find("no blocks and no orthant") != std::string::npos);
  SdpSettings s;
  s.gap_tolerance = 0.0;
  CHECK(message_of([&] { s.validate(); }).find("gap_tolerance must be > 0") != std::string::npos);
  CHECK(message_of([] { (void)sdp_solver_from_string("mosek"); }) ==
        "unknown convex::SdpSolver 'mosek' (valid: dsdp, sdpa)");
  // SDPA ends the process on m = 0; solve_sdp refuses first.
  Sdp none = smallest_eigenvalue(Eigen::Matrix3d::Identity());
  none.a.clear();
  none.b.clear();
  s = {};
  s.solver = SdpSolver::sdpa;
  CHECK(message_of([&] { (void)solve_sdp(none, s); }).find("SDPA needs at least one constraint") !=
        std::string::npos);
}

// DSDP and SDPA call the BLAS, so it is loaded here: trial loops run it on one thread (core/blas.hpp) and
// give its count back afterwards.
TEST_CASE("trial loops run OpenBLAS on one thread and give its thread count back") {
  namespace core = keel::core;
  if (core::blas_threads() == 0) {
    // Another BLAS than OpenBLAS (Debian's alternatives): the calls do nothing and say so.
    MESSAGE("the loaded BLAS is not OpenBLAS");
    CHECK(core::set_blas_threads(2) == 0);
    return;
  }
  const int before = core::set_blas_threads(2);
  REQUIRE(core::blas_threads() == 2);
  for (const unsigned threads : {1u, 2u}) {
    std::vector<int> seen(16, 0);
    core::parallel_for(seen.size(), [&](std::size_t i) { seen[i] = core::blas_threads(); }, threads);
    for (const int s : seen) CHECK(s == 1);
    CHECK(core::blas_threads() == 2);
  }
  {
    const core::SingleThreadedBlas guard;
    CHECK(core::blas_threads() == 1);
  }
  CHECK(core::blas_threads() == 2);
  // Guards on two threads that overlap: the count stays 1 until the last of them ends, whichever began first.
  {
    std::optional<core::SingleThreadedBlas> first(std::in_place);
    std::promise<void> second_began, first_ended;
    std::thread other([&] {
      const core::SingleThreadedBlas second;
      second_began.set_value();
      first_ended.get_future().wait();
      CHECK(core::blas_threads() == 1);  // the first guard ended; this one still holds
    });
    second_began.get_future().wait();
    first.reset();
    CHECK(core::blas_threads() == 1);
    first_ended.set_value();
    other.join();
  }
  CHECK(core::blas_threads() == 2);
  core::set_blas_threads(before);
}
