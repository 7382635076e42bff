// libFuzzer target: every text reader of keel.graph (graphs, candidate edge files, pose lists) on the same
// bytes (in memory, through the std::istream overloads). A reader may only succeed or throw
// keel::graph::ParseError; any other exception, a crash, a hang or a sanitizer report is a bug. When a graph
// reader succeeds, its writer must write the graph back so that the reader gives the same graph again (the
// round-trip property of engine/graph): a violation aborts with the difference.
#include <fmt/format.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"
#include "graph/trajectory.hpp"

using namespace keel::graph;

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
  fmt::print(stderr, "fuzz_readers: {}: {}\n", what, detail);
  std::abort();
}

template <class F>
void expect_parse_error_only(const char* what, F&& f) {
  try {
    f();
  } catch (const ParseError&) {
  } catch (const std::exception& e) {
    fail(what, fmt::format("unexpected exception: {}", e.what()));
  } catch (...) {
    fail(what, "unexpected non-std exception");
  }
}

// Chained poses may lose a few ulps per step when written and read again; compare them against the size of
// the translations that built them.
template <class Graph>
double pose_scale(const Graph& g) {
  double s = 1.0;
  for (const auto& e : g.edges) s += e.measurement.translation().norm();
  return s;
}

// `poses`: false when the written format cannot hold a's poses (iSAM text has no vertices, so a graph whose
// poses came from VERTEX lines comes back with the chained odometry instead).
template <class Graph>
void compare(const char* what, const Graph& a, Graph b, bool poses) {
  double worst = 0.0;
  if (!poses && a.poses.size() == b.poses.size()) b.poses = a.poses;
  if (a.poses.size() == b.poses.size()) {
    for (std::size_t k = 0; k < a.poses.size(); ++k) {
      worst = std::max(worst, (a.poses[k].matrix() - b.poses[k].matrix()).cwiseAbs().maxCoeff());
    }
    if (!(worst <= 1e-9 * pose_scale(a))) fail(what, "poses differ after the round trip");
    b.poses = a.poses;
  }
  if (auto d = graph_difference(a, b, 1e-9); !d.empty()) fail(what, d);
}

// `cross`: writing into the other format, whose writer may refuse (std::invalid_argument) what that format
// cannot hold (an iSAM file needs the odometry chain; a g2o file holds no landmarks).
template <class Graph, class Write, class Read>
void round_trip(const char* what, const Graph& g, Write write, Read read, bool poses = true,
                bool cross = false) {
  std::ostringstream out;
  try {
    write(g, out);
  } catch (const std::invalid_argument&) {
    if (cross) return;
    fail(what, "the writer refused a graph its reader accepted");
  } catch (const std::exception& e) {
    fail(what, fmt::format("the writer refused a graph its reader accepted: {}", e.what()));
  }
  std::istringstream in(out.str());
  Graph back;
  try {
    back = read(in);
  } catch (const std::exception& e) {
    fail(what, fmt::format("the reader rejected the writer's output: {}\n{}", e.what(), out.str()));
  }
  compare(what, g, back, poses);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto in = [&]() { return std::istringstream(text); };

  expect_parse_error_only("read_g2o_2d", [&] {
    auto s = in();
    const PoseGraph2D g = read_g2o_2d(s, "fuzz.g2o");
    round_trip(
        "g2o 2D", g, [](const PoseGraph2D& x, std::ostream& o) { write_g2o(x, o); },
        [](std::istream& i) { return read_g2o_2d(i, "rt.g2o"); });
    round_trip(
        "g2o 2D -> iSAM", g, [](const PoseGraph2D& x, std::ostream& o) { write_isam(x, o); },
        [](std::istream& i) { return read_isam_2d(i, "rt.txt"); }, !g.has_initial_poses, true);
  });
  expect_parse_error_only("read_g2o_3d", [&] {
    auto s = in();
    const PoseGraph3D g = read_g2o_3d(s, "fuzz.g2o");
    round_trip(
        "g2o 3D", g, [](const PoseGraph3D& x, std::ostream& o) { write_g2o(x, o); },
        [](std::istream& i) { return read_g2o_3d(i, "rt.g2o"); });
    round_trip(
        "g2o 3D -> iSAM", g, [](const PoseGraph3D& x, std::ostream& o) { write_isam(x, o); },
        [](std::istream& i) { return read_isam_3d(i, "rt.txt"); }, !g.has_initial_poses, true);
  });
  expect_parse_error_only("read_isam_2d", [&] {
    auto s = in();
    const PoseGraph2D g = read_isam_2d(s, "fuzz.txt");
    round_trip(
        "iSAM 2D", g, [](const PoseGraph2D& x, std::ostream& o) { write_isam(x, o); },
        [](std::istream& i) { return read_isam_2d(i, "rt.txt"); });
    if (g.landmark_measurements.empty()) {
      round_trip(
          "iSAM 2D -> g2o", g, [](const PoseGraph2D& x, std::ostream& o) { write_g2o(x, o); },
          [](std::istream& i) { return read_g2o_2d(i, "rt.g2o"); }, true, true);
    }
  });
  expect_parse_error_only("read_isam_3d", [&] {
    auto s = in();
    const PoseGraph3D g = read_isam_3d(s, "fuzz.txt");
    round_trip(
        "iSAM 3D", g, [](const PoseGraph3D& x, std::ostream& o) { write_isam(x, o); },
        [](std::istream& i) { return read_isam_3d(i, "rt.txt"); });
  });
  expect_parse_error_only("read_pose_graph_2d", [&] {
    auto s = in();
    read_pose_graph_2d(s, "fuzz.g2o");
  });
  expect_parse_error_only("read_pose_graph_3d", [&] {
    auto s = in();
    read_pose_graph_3d(s, "fuzz.txt");
  });
  expect_parse_error_only("read_isam_ground_truth_2d", [&] {
    auto s = in();
    read_isam_ground_truth_2d(s, "gt.txt", {.translation_step = 0.5, .angle_step = 1.5707963267948966});
  });
  expect_parse_error_only("read_isam_ground_truth_3d", [&] {
    auto s = in();
    read_isam_ground_truth_3d(s, "gt.txt");
  });
  expect_parse_error_only("read_poses_2d", [&] {
    auto s = in();
    const auto p = read_poses_2d(s, "p.txt");
    std::ostringstream o;
    write_poses_2d(p, o);
    std::istringstream back(o.str());
    if (read_poses_2d(back, "rt.txt").size() != p.size()) fail("poses 2D", "size changed");
  });
  expect_parse_error_only("read_landmarks_2d", [&] {
    auto s = in();
    read_landmarks_2d(s, "l.txt");
  });
  expect_parse_error_only("read_poses_3d", [&] {
    auto s = in();
    const auto p = read_poses_3d(s, "p.txt");
    std::ostringstream o;
    write_tum(p, o);
    std::istringstream back(o.str());
    if (read_tum(back, "rt.tum").size() != p.size()) fail("poses 3D -> TUM", "size changed");
  });
  expect_parse_error_only("read_pose_list_2d", [&] {
    auto s = in();
    read_pose_list_2d(s, "n.dat");
  });
  // Candidate files of `keel pcm` (edge-only g2o).
  expect_parse_error_only("read_g2o_edges_2d", [&] {
    auto s = in();
    read_g2o_edges_2d(s, "cand.g2o");
  });
  expect_parse_error_only("read_g2o_edges_3d", [&] {
    auto s = in();
    read_g2o_edges_3d(s, "cand.g2o");
  });
  expect_parse_error_only("read_tum", [&] {
    auto s = in();
    read_tum(s, "t.tum");
  });
  return 0;
}
