// keel.app's file helpers: the graph summary counts components, duplicates and odometry; the dimension of a
// file comes from its first record; bad labels give located errors.
#include <doctest/doctest.h>

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
