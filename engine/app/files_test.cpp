// keel.app's file helpers: the graph summary counts components, duplicates and odometry; the dimension of a
// file comes from its first record; bad labels give located errors.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/files.hpp"
#include "graph/parse_error.hpp"
#include "kit/test_kit.hpp"

using namespace keel;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("keel_app_test_" + name);
  fs::remove_all(d);
  return d;
}

void write_text(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

}  // namespace

TEST_CASE("graph summary: counts, duplicates, components, dimension") {
  const fs::path dir = scratch("summary");
  fs::create_directories(dir);
  const std::string info = " 100 0 0 100 0 400\n";
  write_text(dir / "g.g2o", "EDGE_SE2 0 1 1 0 0" + info + "EDGE_SE2 1 2 1 0 0" + info +
                                "EDGE_SE2 2 0 -2 0 0" + info + "EDGE_SE2 1 0 -1 0 0" + info +
                                "EDGE_SE2 3 4 1 0 0 100 10 0 100 0 400\n");
  // Pose 3 is not reachable by odometry from 2, so the chained initial estimate needs the vertices.
  write_text(dir / "v.g2o",
             "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nVERTEX_SE2 3 0 5 0\n"
             "VERTEX_SE2 4 1 5 0\nEDGE_SE2 0 1 1 0 0" +
                 info + "EDGE_SE2 1 2 1 0 0" + info + "EDGE_SE2 2 0 -2 0 0" + info + "EDGE_SE2 1 0 -1 0 0" +
                 info + "EDGE_SE2 3 4 1 0 0 100 10 0 100 0 400\n");
  CHECK(app::graph_dimension(dir / "v.g2o") == 2);
  const auto s = app::summarize(dir / "v.g2o");
  CHECK(s.format == "g2o");
  CHECK(s.poses == 5);
  CHECK(s.edges == 5);
  CHECK(s.odometry == 4);  // (0,1), (1,2), (1,0), (3,4)
  CHECK(s.loop_closures == 1);
  CHECK(s.duplicate_edges == 1);
  CHECK(s.components == 2);
  CHECK(s.largest_component == 3);
  CHECK(s.cross_term_edges == 1);
  CHECK(s.sigma_rotation_min == doctest::Approx(0.05));
  CHECK(s.has_initial_poses);
  write_text(dir / "e.g2o", "# only a comment\n");
  CHECK(app::graph_dimension(dir / "e.g2o") == 2);  // the 2D reader then says what is missing
  CHECK(app::graph_dimension("# 3D\nEDGE3 0 1", "mem") == 3);
  CHECK(testkit::throws_with<graph::ParseError>([&] { (void)app::graph_dimension(dir / "missing.g2o"); },
                                                "missing.g2o: cannot open file"));
  write_text(dir / "l.txt", "0 inlier -1\n2 random -1\n");
  CHECK(testkit::throws_with<graph::ParseError>([&] { (void)app::read_labels(dir / "l.txt"); },
                                                "l.txt:2: label field 1 (candidate): expected candidate 1"));
  fs::remove_all(dir);
}

TEST_CASE("check: σ from a factorization of Ω (no determinant over- or underflow)") {
  const fs::path dir = scratch("sigma");
  fs::create_directories(dir);
  // Information 1e-110 on every axis: σ = 1e55 (a 3 × 3 determinant of 1e-330 underflows to 0 and gave σ =
  // ∞).
  write_text(dir / "tiny.g2o", "EDGE_SE2 0 1 1 0 0 1e-110 0 0 1e-110 0 1e-110\n");
  const auto t = app::summarize(dir / "tiny.g2o");
  CHECK(t.sigma_translation_min == doctest::Approx(1e55).epsilon(1e-12));
  CHECK(t.sigma_rotation_max == doctest::Approx(1e55).epsilon(1e-12));
  // Information 4e28 with a cross term: σ_x = √(Ω⁻¹)_xx exactly from the 2 × 2 block formula.
  write_text(dir / "big.g2o", "EDGE_SE2 0 1 1 0 0 4e28 2e28 0 4e28 0 1e28\n");
  const auto b = app::summarize(dir / "big.g2o");
  const double sx = std::sqrt(4e28 / (4e28 * 4e28 - 2e28 * 2e28));
  CHECK(b.sigma_translation_min == doctest::Approx(sx).epsilon(1e-12));
  CHECK(b.sigma_rotation_min == doctest::Approx(1e-14).epsilon(1e-12));
  fs::remove_all(dir);
}

TEST_CASE("check and solve refuse a cost that double precision cannot evaluate: λ_max(Ω)·(ε·M)² ≤ 1") {
  const fs::path dir = scratch("range");
  fs::create_directories(dir);
  const std::string info = " 1 0 0 1 0 1\n";
  for (const char* z : {"1e100", "1e300", "1e20"}) {
    INFO(z);
    write_text(dir / "tree.g2o", fmt::format("EDGE_SE2 0 1 {} 0 0{}EDGE_SE2 1 2 1 0 0{}", z, info, info));
    CHECK(testkit::throws_with<std::invalid_argument>(
        [&] { (void)app::summarize(dir / "tree.g2o"); },
        fmt::format(
            "tree.g2o:1: EDGE_SE2: information of largest eigenvalue 1 at coordinates up to M = {:.4g}",
            std::stod(z) + 1)));
  }
  write_text(dir / "w.g2o", "EDGE_SE2 0 1 1 0 0 1e308 0 0 1 0 1\n");
  CHECK(testkit::throws_with<std::invalid_argument>(
      [&] { (void)app::summarize(dir / "w.g2o"); },
      "w.g2o:1: EDGE_SE2: information of largest eigenvalue 1e+308"));
  // The limit itself: M = 1e6 allows λ_max up to 1/(ε·1e6)² ≈ 2.03e19.
  write_text(dir / "ok.g2o", "EDGE_SE2 0 1 1e6 0 0 2e19 0 0 2e19 0 1\n");
  CHECK(app::summarize(dir / "ok.g2o").edges == 1);
  write_text(dir / "no.g2o", "EDGE_SE2 0 1 1e6 0 0 2.1e19 0 0 2.1e19 0 1\n");
  CHECK_THROWS_AS((void)app::summarize(dir / "no.g2o"), std::invalid_argument);
  fs::remove_all(dir);
}
