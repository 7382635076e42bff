// Readers and writers on synthetic input: round trips of random graphs through every writer/reader pair, the
// exact TUM layout, format dispatch, Euler extraction next to gimbal lock, and one ParseError per
// malformed-input rule, each checked for file, line and field in its message.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/isam.hpp"
#include "graph/parse_error.hpp"
#include "graph/trajectory.hpp"
#include "kit/graph_input.hpp"
#include "kit/test_kit.hpp"
#include "lie/euler.hpp"

using namespace keel::graph;
using keel::lie::kPi;
using keel::lie::SO3;
using keel::lie::Vec3;
using keel::lie::Vec6;
using keel::testkit::error_of;
using keel::testkit::g2o3;
using keel::testkit::kE01;
using keel::testkit::kEdge3Tail;
using keel::testkit::kInfo2;
using keel::testkit::kSqrt2;
using keel::testkit::kV2;

using keel::testkit::random_information;  // information over six orders of magnitude
                                          // (InformationDraw::spread)
using keel::testkit::round_trip;
using keel::testkit::round_trip_file;

namespace {

// Uniform on {0, …, n − 1}.
int pick(keel::core::Rng& rng, int n) { return std::min(n - 1, static_cast<int>(rng.uniform() * n)); }

SE2 random_pose_2d(keel::core::Rng& rng) {
  const double x = rng.uniform(-20.0, 20.0), y = rng.uniform(-20.0, 20.0), th = rng.uniform(-kPi, kPi);
  return SE2(x, y, th);
}

// Random 2D graph: odometry chain (so poses = chained odometry), loop closures, optional landmarks seen from
// random poses (landmarks = first observation), measurements of every size and angle.
PoseGraph2D random_graph_2d(keel::core::Rng& rng, int n, int loops, int landmarks) {
  PoseGraph2D g;
  g.poses.assign(static_cast<std::size_t>(n), SE2());
  for (int k = 0; k + 1 < n; ++k) {
    Edge2 e{k, k + 1, random_pose_2d(rng), random_information<3>(rng), 0};
    g.poses[static_cast<std::size_t>(k + 1)] = g.poses[static_cast<std::size_t>(k)] * e.measurement;
    g.edges.push_back(e);
  }
  for (int k = 0; k < loops; ++k) {
    int i = pick(rng, n), j = pick(rng, n);
    if (i == j) j = (i + 2) % n;
    const SE2 z = random_pose_2d(rng);
    g.edges.push_back({i, j, z, random_information<3>(rng), 0});
  }
  for (int l = 0; l < landmarks; ++l) {
    for (int rep = 0; rep < 3; ++rep) {
      LandmarkMeasurement2 m;
      m.pose = pick(rng, n);
      m.landmark = l;
      m.position.x() = rng.uniform(-20.0, 20.0);
      m.position.y() = rng.uniform(-20.0, 20.0);
      m.information = random_information<2>(rng);
      g.landmark_measurements.push_back(m);
    }
  }
  // Order the landmark measurements by pose (the iSAM writer keeps time order) and set landmarks from the
  // first one.
  std::stable_sort(g.landmark_measurements.begin(), g.landmark_measurements.end(),
                   [](const auto& a, const auto& b) { return a.pose < b.pose; });
  g.landmarks.assign(static_cast<std::size_t>(landmarks), Vec2::Zero());
  std::vector<char> seen(static_cast<std::size_t>(landmarks), 0);
  for (const auto& m : g.landmark_measurements) {
    if (seen[static_cast<std::size_t>(m.landmark)]++) continue;
    g.landmarks[static_cast<std::size_t>(m.landmark)] =
        g.poses[static_cast<std::size_t>(m.pose)] * m.position;
  }
  return g;
}

SE3 random_pose_3d(keel::core::Rng& rng) {
  Vec6 xi;
  for (int k = 0; k < 3; ++k) xi(k) = rng.uniform(-20.0, 20.0);
  for (int k = 3; k < 6; ++k) xi(k) = rng.uniform(-3.0, 3.0);
  return SE3::exp(xi);
}

PoseGraph3D random_graph_3d(keel::core::Rng& rng, int n, int loops) {
  PoseGraph3D g;
  g.poses.assign(static_cast<std::size_t>(n), SE3());
  for (int k = 0; k + 1 < n; ++k) {
    Edge3 e{k, k + 1, random_pose_3d(rng), random_information<6>(rng), 0};
    g.poses[static_cast<std::size_t>(k + 1)] = g.poses[static_cast<std::size_t>(k)] * e.measurement;
    g.edges.push_back(e);
  }
  for (int k = 0; k < loops; ++k) {
    int i = pick(rng, n), j = pick(rng, n);
    if (i == j) j = (i + 2) % n;
    const SE3 z = random_pose_3d(rng);
    g.edges.push_back({i, j, z, random_information<6>(rng), 0});
  }
  return g;
}

}  // namespace

TEST_CASE("g2o 2D round trip of random graphs is exact") {
  keel::core::Rng rng(1);
  for (int t = 0; t < 20; ++t) {
    PoseGraph2D g = random_graph_2d(rng, 2 + t * 5, t * 3, 0);
    const PoseGraph2D back =
        round_trip([&](auto& s) { write_g2o(g, s); }, [](auto& in) { return read_g2o_2d(in, "mem.g2o"); });
    CHECK(back.has_initial_poses);
    CHECK_MESSAGE(graph_difference(g, back, 1e-14).empty(), graph_difference(g, back, 1e-14));
    // Without vertices, the reader chains the odometry: equal to the poses the generator chained.
    const PoseGraph2D chained = round_trip([&](auto& s) { write_g2o(g, s, {.write_vertices = false}); },
                                           [](auto& in) { return read_g2o_2d(in, "mem.g2o"); });
    CHECK_FALSE(chained.has_initial_poses);
    CHECK(graph_difference(g, chained, 1e-9).empty());
  }
}

TEST_CASE("iSAM 2D round trip of random graphs with landmarks") {
  keel::core::Rng rng(2);
  for (int t = 0; t < 20; ++t) {
    const PoseGraph2D g = random_graph_2d(rng, 2 + t * 5, t * 3, t % 4 * 3);
    const PoseGraph2D back =
        round_trip([&](auto& s) { write_isam(g, s); }, [](auto& in) { return read_isam_2d(in, "mem.txt"); });
    CHECK_FALSE(back.has_initial_poses);
    CHECK_MESSAGE(graph_difference(g, back, 1e-9).empty(), graph_difference(g, back, 1e-9));
    // The square-root information reproduces Ω to rounding.
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      CHECK((g.edges[k].information - back.edges[k].information).norm() <=
            1e-13 * g.edges[k].information.norm());
    }
  }
}

TEST_CASE("g2o and iSAM 3D round trips of random graphs") {
  keel::core::Rng rng(3);
  for (int t = 0; t < 20; ++t) {
    const PoseGraph3D g = random_graph_3d(rng, 2 + t * 4, t * 2);
    const PoseGraph3D from_g2o =
        round_trip([&](auto& s) { write_g2o(g, s); }, [](auto& in) { return read_g2o_3d(in, "mem.g2o"); });
    CHECK_MESSAGE(graph_difference(g, from_g2o, 1e-13).empty(), graph_difference(g, from_g2o, 1e-13));
    const PoseGraph3D from_isam =
        round_trip([&](auto& s) { write_isam(g, s); }, [](auto& in) { return read_isam_3d(in, "mem.txt"); });
    CHECK_MESSAGE(graph_difference(g, from_isam, 1e-9).empty(), graph_difference(g, from_isam, 1e-9));
  }
}

TEST_CASE("g2o 3D information is converted between (t, q_vec) and (t, φ)") {
  // Ω_g2o = diag(1, 2, 3, 4, 8, 12) over (t, q_vec): over (t, φ) with q_vec = φ/2 it is diag(1, 2, 3, 1, 2,
  // 3).
  const std::string text =
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 2 0 0 0 0 3 0 0 0 4 0 0 8 0 12\n";
  std::istringstream in(text);
  const PoseGraph3D g = read_g2o_3d(in, "mem.g2o");
  REQUIRE(g.edges.size() == 1);
  Mat6 expected = Mat6::Zero();
  expected.diagonal() << 1, 2, 3, 1, 2, 3;
  CHECK((g.edges[0].information - expected).norm() == 0.0);
  std::ostringstream out;
  write_g2o(g, out);
  CHECK(out.str().find("EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 2 0 0 0 0 3 0 0 0 4 0 0 8 0 12\n") !=
        std::string::npos);
}

TEST_CASE("iSAM square-root information: Ω = RᵀR, upper triangle row by row") {
  // R = [[1, 2, 3], [0, 4, 5], [0, 0, 6]] -> RᵀR.
  std::istringstream in("EDGE2 0 1 1 0 0 1 2 3 4 5 6\nLANDMARK 1 0 2 3 2 1 3\n");
  const PoseGraph2D g = read_isam_2d(in, "mem.txt");
  Mat3 R;
  R << 1, 2, 3, 0, 4, 5, 0, 0, 6;
  CHECK((g.edges[0].information - R.transpose() * R).norm() == 0.0);
  Mat2 L;
  L << 2, 1, 0, 3;
  CHECK((g.landmark_measurements[0].information - L.transpose() * L).norm() == 0.0);
  CHECK(g.landmarks.size() == 1);
  CHECK((g.landmarks[0] - Vec2(3, 3)).norm() < 1e-15);  // pose 1 = (1, 0, 0), landmark at (2, 3) in its frame
  // EDGE3: x y z roll pitch yaw, R = Rz(yaw) Ry(pitch) Rx(roll); 21 numbers of the 6×6 square root.
  std::istringstream in3("EDGE3 0 1 1 2 3 0.1 0.2 0.3 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25\n");
  const PoseGraph3D g3 = read_isam_3d(in3, "mem.txt");
  CHECK((g3.edges[0].measurement.rotation() - keel::lie::rotation_from_rpy(0.1, 0.2, 0.3)).norm() < 1e-15);
  Vec6 diag;
  diag << 100, 100, 100, 1e4, 1e4, 625;
  CHECK((g3.edges[0].information.diagonal() - diag).norm() == 0.0);
  CHECK((g3.poses[1].translation() - Vec3(1, 2, 3)).norm() == 0.0);
}

TEST_CASE("rpy_for_writing reproduces rotations next to gimbal lock") {
  keel::core::Rng rng(4);
  for (double eps : {0.0, 1e-15, 1e-12, 1e-9, 1e-6, 1e-3, 0.5}) {
    for (double sign : {1.0, -1.0}) {
      for (int t = 0; t < 50; ++t) {
        const double roll = rng.uniform(-kPi, kPi), yaw = rng.uniform(-kPi, kPi);
        const Mat3 R = keel::lie::rotation_from_rpy(roll, sign * (0.5 * kPi - eps), yaw);
        const Vec3 rpy = rpy_for_writing(R);
        CHECK((keel::lie::rotation_from_rpy(rpy(0), rpy(1), rpy(2)) - R).norm() < 1e-14);
      }
    }
  }
}

TEST_CASE("derived pose lists, landmarks and TUM round trip") {
  keel::core::Rng rng(5);
  const PoseGraph2D g = random_graph_2d(rng, 30, 0, 4);
  const auto poses = round_trip([&](auto& s) { write_poses_2d(g.poses, s); },
                                [](auto& in) { return read_poses_2d(in, "p.txt"); });
  const auto lms = round_trip([&](auto& s) { write_landmarks_2d(g.landmarks, s); },
                              [](auto& in) { return read_landmarks_2d(in, "l.txt"); });
  REQUIRE(poses.size() == g.poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) CHECK(poses[k].is_approx(g.poses[k], 1e-13));
  REQUIRE(lms.size() == g.landmarks.size());
  for (std::size_t k = 0; k < lms.size(); ++k) CHECK(lms[k] == g.landmarks[k]);
  const PoseGraph3D g3 = random_graph_3d(rng, 30, 0);
  const auto p3 = round_trip([&](auto& s) { write_poses_3d(g3.poses, s); },
                             [](auto& in) { return read_poses_3d(in, "p3.txt"); });
  for (std::size_t k = 0; k < p3.size(); ++k) CHECK(p3[k].is_approx(g3.poses[k], 1e-13));
  const auto tum =
      round_trip([&](auto& s) { write_tum(g3.poses, s); }, [](auto& in) { return read_tum(in, "t.tum"); });
  REQUIRE(tum.size() == g3.poses.size());
  for (std::size_t k = 0; k < tum.size(); ++k) {
    CHECK(tum[k].timestamp == static_cast<double>(k));
    CHECK(tum[k].pose.is_approx(g3.poses[k], 1e-13));
  }
  // Ids may come in any order, but each once and contiguous from 0.
  std::istringstream shuffled("2 0 0 0\n0 1 0 0\n1 2 0 0\n");
  const auto sh = read_poses_2d(shuffled, "s.txt");
  CHECK(sh[0].translation().x() == 1.0);
  CHECK(sh[2].translation().x() == 0.0);
}

TEST_CASE("TUM output format: timestamp = index, 2D poses in the plane z = 0") {
  std::ostringstream s;
  write_tum(std::vector<SE2>{SE2(1.5, -2.0, 0.5 * kPi), SE2(0, 0, kPi), SE2(3, 4, -0.25)}, s);
  std::istringstream lines(s.str());
  std::string line;
  int k = 0;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    std::vector<double> v;
    double x;
    while (f >> x) v.push_back(x);
    REQUIRE(v.size() == 8);
    CHECK(v[0] == k);
    CHECK(v[3] == 0.0);  // z
    CHECK(v[4] == 0.0);  // qx
    CHECK(v[5] == 0.0);  // qy
    CHECK(v[7] >= 0.0);  // qw
    CHECK(v[6] * v[6] + v[7] * v[7] == doctest::Approx(1.0));
    ++k;
  }
  CHECK(k == 3);
  CHECK(s.str().rfind("0 1.5 -2 0 0 0 0.70710678118654746 0.70710678118654757\n", 0) == 0);
  CHECK(s.str().find("\n1 0 0 0 0 0 1 6.123233995736766e-17\n") != std::string::npos);
}

TEST_CASE("format dispatch by first tag, extension as fallback") {
  CHECK(detect_graph_format("# c\n\nVERTEX_SE2 0 0 0 0\n", "x.txt") == GraphFormat::g2o);
  CHECK(detect_graph_format("EDGE3 0 1", "x.g2o") == GraphFormat::isam);
  CHECK(detect_graph_format("", "x.g2o") == GraphFormat::g2o);
  CHECK(detect_graph_format("# only a comment\n", "x.txt") == GraphFormat::isam);
  CHECK_FALSE(detect_graph_format("FOO 1 2\n", "x.g2o").has_value());
  for (GraphFormat f : {GraphFormat::g2o, GraphFormat::isam})
    CHECK(graph_format_from_string(to_string(f)) == f);
  CHECK(to_string(GraphFormat::g2o) == "g2o");
  CHECK(keel::testkit::throws_with<std::invalid_argument>(
      [] { (void)graph_format_from_string("G2O"); }, "unknown graph::GraphFormat 'G2O' (valid: g2o, isam)"));
  std::istringstream a(kV2 + kE01);
  CHECK(read_pose_graph_2d(a, "a.txt").edges.size() == 1);
  std::istringstream b("EDGE2 0 1 1 0 0" + kSqrt2 + "\n");
  CHECK(read_pose_graph_2d(b, "b.g2o").edges[0].information(2, 2) == 1e4);
  std::istringstream c("EDGE3 0 1 0 0 0 0 0 0" + kEdge3Tail + "\n");
  CHECK(read_pose_graph_3d(c, "c.txt").poses.size() == 2);
  std::istringstream d("EDGE3 0 1 0 0 0 0 0 0" + kEdge3Tail + "\n");
  const std::string msg = error_of([&] { read_pose_graph_2d(d, "d.txt"); });
  CHECK_CONTAINS(msg, "d.txt:1: 'EDGE3' is a 3D record");
  CHECK_CONTAINS(msg, "read_pose_graph_3d");
  std::istringstream e("FOO 1 2\n");
  CHECK_CONTAINS(error_of([&] { read_pose_graph_2d(e, "e.g2o"); }), "e.g2o:1: unknown tag 'FOO'");
}

TEST_CASE("comments, blank lines, tabs and CRLF are accepted") {
  const std::string text =
      "# header\r\n\r\nVERTEX_SE2 0 0 0 0 # origin\r\n\tVERTEX_SE2\t1 1 0 0\r\n" + kE01 + "#\n";
  std::istringstream in(text);
  const PoseGraph2D g = read_g2o_2d(in, "ok.g2o");
  CHECK(g.poses.size() == 2);
  CHECK(g.edges.size() == 1);
  CHECK(g.edges[0].line == 5);
}

TEST_CASE("writers reject what their format cannot hold") {
  keel::core::Rng rng(6);
  PoseGraph2D g = random_graph_2d(rng, 5, 2, 2);
  std::ostringstream s;
  CHECK_THROWS_AS(write_g2o(g, s), std::invalid_argument);
  g.landmarks.clear();
  g.landmark_measurements.clear();
  g.edges[0].information(2, 2) = -1.0;
  CHECK_THROWS_AS(write_isam(g, s), std::invalid_argument);
  g.edges[0].information(2, 2) = 1.0;
  g.edges[0].j = 99;
  CHECK_THROWS_AS(write_g2o(g, s), std::invalid_argument);
  CHECK_THROWS_AS(write_pose_graph(g, std::filesystem::path("x.csv")), std::invalid_argument);
  // iSAM text holds no vertices: a graph its readers could not chain is refused, not written half.
  std::istringstream gap(kV2 + "VERTEX_SE2 2 0 0 0\n" + kE01 + "EDGE_SE2 0 2 1 0 0" + kInfo2 + "\n");
  const PoseGraph2D no_chain = read_g2o_2d(gap, "gap.g2o");
  CHECK_THROWS_WITH_AS(write_isam(no_chain, s), doctest::Contains("no odometry edge (1, 2)"),
                       std::invalid_argument);
  std::istringstream lone("VERTEX_SE2 0 1 2 3\n");
  const PoseGraph2D single = read_g2o_2d(lone, "lone.g2o");
  CHECK(single.poses.size() == 1);
  CHECK_THROWS_WITH_AS(write_isam(single, s), doctest::Contains("no edges"), std::invalid_argument);
}

TEST_CASE("ground truth of a synthetic grid: snapping makes the chain exact") {
  // A square loop printed with 6 digits: 4 steps of (1, 0, π/2) and the closing edge (3 -> 0).
  const std::string noise = " 50 0 0 50 0 100\n";
  std::string text;
  for (int k = 0; k < 3; ++k) text += fmt::format("EDGE2 {} {} 1 0 1.5708{}", k, k + 1, noise);
  text += fmt::format("EDGE2 3 0 1 -0 1.5708{}LANDMARK 2 0 0.5 -0.5 10 0 10\n", noise);
  std::istringstream raw(text);
  const GroundTruth2D loose = read_isam_ground_truth_2d(raw, "gt.txt");
  CHECK(loose.max_edge_rotation_error > 1e-6);
  std::istringstream again(text);
  const GroundTruth2D exact =
      read_isam_ground_truth_2d(again, "gt.txt", {.translation_step = 0.5, .angle_step = 0.5 * kPi});
  CHECK(exact.max_edge_translation_error < 1e-15);
  CHECK(exact.max_edge_rotation_error < 1e-15);
  CHECK(exact.poses[2].translation() == Vec2(1, 1));
  CHECK(exact.landmarks[0] == Vec2(0.5, 1.5));  // pose 2 = (1, 1, π)
}

TEST_CASE("edge-only g2o files (inter-robot candidates): exact round trip, two id spaces, located errors") {
  namespace fs = std::filesystem;
  keel::core::Rng rng(11);
  const PoseGraph2D g2 = random_graph_2d(rng, 12, 6, 0);
  const PoseGraph3D g3 = random_graph_3d(rng, 12, 6);
  std::vector<Edge2> e2 = g2.edges;
  std::vector<Edge3> e3 = g3.edges;
  e2[0].j = e2[0].i;  // the ids are in two id spaces: (i, i) is a valid candidate
  e3[0].j = e3[0].i;
  const auto b2 = round_trip_file(
      "keel_edges_2d.g2o", [&](const fs::path& f) { write_g2o_edges(e2, f); },
      [](const fs::path& f) { return read_g2o_edges_2d(f); });
  const auto b3 = round_trip_file(
      "keel_edges_3d.g2o", [&](const fs::path& f) { write_g2o_edges(e3, f); },
      [](const fs::path& f) { return read_g2o_edges_3d(f); });
  REQUIRE(b2.size() == e2.size());
  REQUIRE(b3.size() == e3.size());
  for (std::size_t k = 0; k < e2.size(); ++k) {
    CHECK(b2[k].i == e2[k].i);
    CHECK(b2[k].j == e2[k].j);
    CHECK(b2[k].line == static_cast<int>(k) + 1);
    CHECK((b2[k].measurement.log() - e2[k].measurement.log()).norm() == 0.0);
    // The writer stores the upper triangle (the generator's lower one may differ in the last bit).
    const Mat3 d = b2[k].information - e2[k].information;
    CHECK(d.triangularView<Eigen::Upper>().toDenseMatrix().norm() == 0.0);
  }
  for (std::size_t k = 0; k < e3.size(); ++k) {
    CHECK(b3[k].i == e3[k].i);
    CHECK(b3[k].j == e3[k].j);
    CHECK((b3[k].measurement.matrix() - e3[k].measurement.matrix()).norm() <= 1e-14);
    CHECK((b3[k].information - e3[k].information).norm() <= 1e-12 * e3[k].information.norm());
  }

  auto edges2 = [](const std::string& text) {
    return error_of([&] {
      std::istringstream in(text);
      (void)read_g2o_edges_2d(in, "cand.g2o");
    });
  };
  CHECK_CONTAINS(edges2("VERTEX_SE2 0 0 0 0\n"),
                 "cand.g2o:1: unexpected tag 'VERTEX_SE2': an edge file holds EDGE_SE2 records only");
  CHECK_CONTAINS(edges2("# nothing\n"), "cand.g2o: no EDGE_SE2 record (an empty edge file)");
  CHECK_CONTAINS(edges2("EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n"), "cand.g2o:1: EDGE_SE2: expected 11 fields");
  CHECK_CONTAINS(edges2("EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n"), "cand.g2o:1: EDGE_SE2 fields 6-11");
  const std::string m3 = error_of([] {
    std::istringstream in("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
    (void)read_g2o_edges_3d(in, "cand3.g2o");
  });
  CHECK_CONTAINS(m3, "cand3.g2o:1: unexpected tag 'EDGE_SE2': an edge file holds EDGE_SE3:QUAT records only");
}

TEST_CASE("g2o information read for the isotropic model: only the diagonal blocks, indefinite ones counted") {
  const std::string v = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n";
  // Identity blocks, coupling I15 = 5 between translation x and rotation y: the 6 × 6 matrix is indefinite.
  const std::string coupled =
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1  1 0 0 0 5 0  1 0 0 0 0  1 0 0 0  1 0 0  1 0  1\n";
  const std::string fine = "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1" + kEdge3Tail + "\n";
  CHECK_CONTAINS(g2o3(v + coupled), "the information matrix is not positive definite");
  std::istringstream in(v + coupled + fine);
  const auto g = read_g2o_3d(in, "coupled.g2o", InformationCheck::diagonal_blocks);
  CHECK(g.edges.size() == 2);
  CHECK(g.indefinite_information == 1);
  CHECK(g.edges[0].information(0, 4) == doctest::Approx(2.5));  // (t, q_vec) → (t, φ): the coupling halves
  // A diagonal block that is not positive definite is refused even so, naming the block.
  const std::string bad_rotation =
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1  1 0 0 0 0 0  1 0 0 0 0  1 0 0 0  -1 0 0  1 0  1\n";
  std::istringstream in2(v + bad_rotation);
  std::string m;
  try {
    (void)read_g2o_3d(in2, "bad.g2o", InformationCheck::diagonal_blocks);
  } catch (const ParseError& e) {
    m = e.what();
  }
  CHECK_CONTAINS(m,
                 "bad.g2o:3: EDGE_SE3:QUAT fields 10-30 (I11..I66): the information matrix's rotation block");
  // 2D: the rotation entry alone.
  std::istringstream in3("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 3 1 0 1\n");
  const auto g2 = read_g2o_2d(in3, "coupled2.g2o", InformationCheck::diagonal_blocks);
  CHECK(g2.indefinite_information == 1);
}

TEST_CASE(
    "g2o FIX k makes pose k the gauge (2D and 3D; repeats allowed; the writer keeps it); FIX decides no "
    "format") {
  std::istringstream in("FIX 0\n" + kV2 + kE01 + "FIX 0\n");
  const auto g = read_g2o_2d(in, "fix.g2o");
  CHECK(g.poses.size() == 2);
  CHECK(g.edges.size() == 1);
  CHECK(g.gauge_pose == 0);
  // FIX before the vertex it names, repeated, on a 3-pose graph: the gauge is pose 2.
  const std::string v3 = kV2 + "VERTEX_SE2 2 1 1 0.5\n";
  const std::string e3 = kE01 + "EDGE_SE2 1 2 0 1 0.5" + kInfo2 + "\n";
  std::istringstream in2("FIX 2\n" + v3 + e3 + "FIX 2 2\n");
  PoseGraph2D g2 = read_g2o_2d(in2, "fix2.g2o");
  CHECK(g2.gauge_pose == 2);
  std::istringstream any("FIX 2\n" + v3 + e3);  // format detection skips the FIX line
  CHECK(read_pose_graph_2d(any, "f.txt").gauge_pose == 2);
  std::ostringstream out;
  write_g2o(g2, out);
  CHECK(out.str().find("\nFIX 2\n") != std::string::npos);
  std::istringstream back(out.str());
  CHECK(read_g2o_2d(back, "back.g2o").gauge_pose == 2);
  g2.gauge_pose = 0;  // the default gauge writes no FIX line
  std::ostringstream out0;
  write_g2o(g2, out0);
  CHECK(out0.str().find("FIX") == std::string::npos);
  g2.gauge_pose = 3;
  CHECK_THROWS_WITH_AS(write_g2o(g2, out0), "write_g2o: the gauge pose 3 is outside the graph (3 poses)",
                       std::invalid_argument);
  // iSAM text has no FIX record: a graph with another gauge is refused, not written without it.
  g2.gauge_pose = 1;
  CHECK_THROWS_WITH_AS(write_isam(g2, out0), doctest::Contains("write_isam: the graph holds pose 1 fixed"),
                       std::invalid_argument);
  // 3D.
  const std::string q = " 0 0 0 1";
  const std::string v3d = "VERTEX_SE3:QUAT 0 0 0 0" + q + "\nVERTEX_SE3:QUAT 1 1 0 0" + q +
                          "\nVERTEX_SE3:QUAT 2 1 1 0" + q + "\n";
  const std::string e3d =
      "EDGE_SE3:QUAT 0 1 1 0 0" + q + kEdge3Tail + "\nEDGE_SE3:QUAT 1 2 0 1 0" + q + kEdge3Tail + "\n";
  std::istringstream in3(v3d + "FIX 1\n" + e3d);
  const PoseGraph3D g3 = read_g2o_3d(in3, "fix3.g2o");
  CHECK(g3.gauge_pose == 1);
  std::ostringstream out3;
  write_g2o(g3, out3);
  std::istringstream back3(out3.str());
  CHECK(read_g2o_3d(back3, "back3.g2o").gauge_pose == 1);
  CHECK_CONTAINS(g2o3(v3d + e3d + "FIX 7\n"),
                 "bad.g2o:6: FIX field 1: '7': no pose 7 in the graph (its 3 poses have ids 0 to 2)");
  CHECK_CONTAINS(
      g2o3(v3d + "FIX 1\n" + e3d + "FIX 2\n"),
      "bad.g2o:7: FIX field 1: '2': keel holds one pose fixed (the gauge), and FIX field 1 on line "
      "4 already fixes pose 1; this one names pose 2");
  CHECK(detect_graph_format("FIX 0\nVERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n", "x.txt") == GraphFormat::g2o);
  CHECK(detect_graph_format("FIX 0\nEDGE2 0 1 1 0 0 1 0 0 1 0 1\n", "x.g2o") == GraphFormat::isam);
}

TEST_CASE("a file is read once: a FIFO works; a directory or a missing file is 'file: reason'") {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("keel_io_fifo_{}", ::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto fifo = dir / "g.g2o";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::thread writer([&] {
    std::ofstream out(fifo);
    out << kV2 << kE01;
  });
  const auto g = read_pose_graph_2d(fifo);
  writer.join();
  CHECK(g.edges.size() == 1);
  CHECK_CONTAINS(error_of([&] { (void)read_pose_graph_2d(dir); }),
                 fmt::format("{}: cannot read: is a directory, not a file", dir.string()));
  CHECK_CONTAINS(error_of([&] { (void)read_pose_graph_2d(dir / "missing.g2o"); }),
                 "missing.g2o: cannot open file (No such file or directory)");
  std::filesystem::remove_all(dir);
}
