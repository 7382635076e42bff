// The real benchmark files, read through the manifest resolver (datasets/manifest.toml; the shared copy in
// ../shared/datasets is found without fetching): counts against SOURCE.md, read → write → read round trips,
// the square-root-information reading checked against the measured noise, ground-truth chaining against the
// derived files, and the resolver's own behaviour (search order, sha256 check, error text). The test cases
// that need the data are in the doctest suite "datasets" (CTest datasets.datasets, label "datasets";
// unit.datasets runs the rest): without a verified copy of a file they fail, naming the file and
// scripts/fetch-datasets (tests/kit/dataset_files.hpp); nothing skips them.
#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <fmt/format.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "datasets/manifest.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/isam.hpp"
#include "datasets/sha256.hpp"
#include "graph/trajectory.hpp"
#include "kit/dataset_files.hpp"
#include "kit/test_kit.hpp"

using namespace keel::datasets;
using namespace keel::graph;
using keel::lie::kPi;
using keel::lie::Vec3;
using keel::lie::Vec6;
using keel::testkit::round_trip;
using keel::testkit::round_trip_file;
namespace fs = std::filesystem;

namespace {

fs::path source_root() { return fs::path(KEEL_SOURCE_DIR); }

// The verified copy of a data set file of this checkout; the test case fails naming the file and the fetch
// command when there is none.
fs::path data(const std::string& name, const std::string& path) {
  return keel::testkit::dataset_file(name, path, source_root());
}

int odometry_count(const auto& g) {
  int n = 0;
  for (const auto& e : g.edges) n += e.j == e.i + 1;
  return n;
}

// Per-component sample standard deviation of whitened residuals.
struct Spread {
  std::vector<double> sum, sum2;
  int n = 0;
  explicit Spread(int dim) : sum(dim, 0.0), sum2(dim, 0.0) {}
  template <class V>
  void add(const V& w) {
    for (int k = 0; k < static_cast<int>(sum.size()); ++k) {
      sum[k] += w(k);
      sum2[k] += w(k) * w(k);
    }
    ++n;
  }
  double std(int k) const {
    const double m = sum[k] / n;
    return std::sqrt(sum2[k] / n - m * m);
  }
};

// w = Lᵀ r with Ω = L Lᵀ: unit covariance when Ω is the inverse covariance of r.
template <int N>
Eigen::Matrix<double, N, 1> whiten(const Eigen::Matrix<double, N, N>& W,
                                   const Eigen::Matrix<double, N, 1>& r) {
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(W);
  return llt.matrixL().transpose() * r;
}

// The same six (or three, or 21) numbers read as g2o would: as the information itself. Ω = RᵀR with R = chol
// upper, so the file's numbers are R; the "information reading" is R's upper triangle symmetrised.
template <int N>
Eigen::Matrix<double, N, N> numbers_read_as_information(const Eigen::Matrix<double, N, N>& W) {
  const Eigen::Matrix<double, N, N> R = Eigen::LLT<Eigen::Matrix<double, N, N>>(W).matrixU();
  return R.template selfadjointView<Eigen::Upper>();
}

Vec3 rho(const SE2& E) { return Vec3(E.translation().x(), E.translation().y(), E.angle()); }
Vec6 rho(const SE3& E) {
  Vec6 r;
  r << E.translation(), E.so3().log();
  return r;
}

struct NoiseCheck {
  std::vector<double> sqrt_reading, information_reading;
};

template <class Graph>
NoiseCheck edge_noise(const Graph& noisy, const Graph& truth) {
  constexpr int N = std::is_same_v<Graph, PoseGraph2D> ? 3 : 6;
  REQUIRE(noisy.edges.size() == truth.edges.size());
  Spread right(N), wrong(N);
  for (std::size_t k = 0; k < noisy.edges.size(); ++k) {
    const auto& e = noisy.edges[k];
    const auto& t = truth.edges[k];
    REQUIRE(e.i == t.i);
    REQUIRE(e.j == t.j);
    const auto r = rho(t.measurement.inverse() * e.measurement);
    right.add(whiten<N>(e.information, r));
    wrong.add(whiten<N>(numbers_read_as_information<N>(e.information), r));
  }
  NoiseCheck out;
  for (int k = 0; k < N; ++k) {
    out.sqrt_reading.push_back(right.std(k));
    out.information_reading.push_back(wrong.std(k));
  }
  return out;
}

void check_unit(const std::vector<double>& s, double tol) {
  if (std::getenv("KEEL_GRAPH_TEST_VERBOSE")) {
    for (double v : s) fmt::print(stderr, " {:.4f}", v);
    fmt::print(stderr, "\n");
  }
  for (std::size_t k = 0; k < s.size(); ++k)
    CHECK_MESSAGE(std::abs(s[k] - 1.0) < tol, "component ", k, ": ", s[k]);
}
void check_far(const std::vector<double>& s) {
  if (std::getenv("KEEL_GRAPH_TEST_VERBOSE")) {
    for (double v : s) fmt::print(stderr, " ({:.4f})", v);
    fmt::print(stderr, "\n");
  }
  bool any_far = false;
  for (double v : s) any_far = any_far || std::abs(v - 1.0) > 0.5;
  CHECK_MESSAGE(any_far, "the information reading should be far from unit spread");
}

}  // namespace

TEST_CASE("manifest lists every file and each resolves to a verified copy" *
          doctest::test_suite("datasets")) {
  const DatasetManifest m = load_dataset_manifest(source_root() / "datasets" / "manifest.toml");
  std::size_t files = 0;
  for (const auto& d : m.datasets) {
    CHECK_FALSE(d.citation.empty());
    for (const auto& f : d.files) {
      ++files;
      const fs::path p = data(d.name, f.path);
      CHECK(fs::file_size(p) == static_cast<std::uintmax_t>(f.bytes));
      if (f.derived) {
        CHECK_FALSE(f.derived_from.empty());
        CHECK_FALSE(f.generator.empty());
      } else if (!f.system_path.empty()) {
        CHECK(f.git_blob.size() == 40);
        CHECK_FALSE(f.debian_package.empty());
        CHECK_FALSE(f.package_version.empty());
      } else {
        CHECK(f.commit.size() == 40);
        CHECK(f.git_blob.size() == 40);
        CHECK_FALSE(f.repository.empty());
      }
    }
  }
  CHECK(m.datasets.size() == 8);  // … se-sync-benchmarks (11 files) and matplotlib-terrain (4)
  CHECK(files == 39);
}

TEST_CASE("counts match SOURCE.md" * doctest::test_suite("datasets")) {
  struct Count2 {
    const char* name;
    const char* path;
    std::size_t poses, edges;
    int odometry;
    bool vertices;
  };
  const Count2 twod[] = {
      {"manhattan3500", "isam/manhattanOlson3500.txt", 3500, 5598, 3499, false},
      {"manhattan3500", "isam/groundtruth/manhattanOlson3500_groundtruth.txt", 3500, 5598, 3499, false},
      {"manhattan3500", "se-sync/manhattan.g2o", 3500, 5453, 3499, false},
      {"manhattan3500", "vertigo/originalDataset/g2o/manhattanOlson3500.g2o", 3500, 5598, 3499, true},
      {"manhattan3500", "vertigo/originalDataset/Olson/manhattanOlson3500.g2o", 3500, 5598, 3499, true},
      {"manhattan3500", "tiny-solver-rs/input_M3500_g2o.g2o", 3500, 5453, 3499, true},
      {"city10000", "isam/city10000.txt", 10000, 20687, 9999, false},
      {"city10000", "isam/groundtruth/city10000_groundtruth.txt", 10000, 20687, 9999, false},
      {"city10000", "se-sync/city10000.g2o", 10000, 20687, 9999, true},
      {"cityTrees10000", "isam/cityTrees10000.txt", 10000, 9999, 9999, false},
      {"intel", "se-sync/intel.g2o", 1728, 2512, 1727, true},
      {"intel", "vertigo/originalDataset/intel.g2o", 943, 1837, 942, true},
  };
  for (const auto& c : twod) {
    CAPTURE(c.path);
    const PoseGraph2D g = read_pose_graph_2d(data(c.name, c.path));
    CHECK(g.poses.size() == c.poses);
    CHECK(g.edges.size() == c.edges);
    CHECK(odometry_count(g) == c.odometry);
    CHECK(g.has_initial_poses == c.vertices);
  }
  const PoseGraph2D trees = read_isam_2d(data("cityTrees10000", "isam/cityTrees10000.txt"));
  CHECK(trees.landmarks.size() == 100);
  CHECK(trees.landmark_measurements.size() == 4443);
  struct Count3 {
    const char* name;
    const char* path;
    std::size_t poses, edges;
    int odometry;
  };
  const Count3 threed[] = {
      {"sphere2500", "isam/sphere2500.txt", 2500, 4949, 2499},
      {"sphere2500", "isam/groundtruth/sphere2500_groundtruth.txt", 2500, 4949, 2499},
      {"sphere2500", "se-sync/sphere2500.g2o", 2500, 4949, 2499},
      {"parking-garage", "se-sync/parking-garage.g2o", 1661, 6275, 1660},
  };
  for (const auto& c : threed) {
    CAPTURE(c.path);
    const PoseGraph3D g = read_pose_graph_3d(data(c.name, c.path));
    CHECK(g.poses.size() == c.poses);
    CHECK(g.edges.size() == c.edges);
    CHECK(odometry_count(g) == c.odometry);
  }
  CHECK(
      read_pose_list_2d(data("manhattan3500", "vertigo/groundTruth/manhattanOlson3500_nodes_groundTruth.dat"))
          .size() == 3500);
}

TEST_CASE("real files: read -> write -> read gives the same graph" * doctest::test_suite("datasets")) {
  const std::pair<const char*, const char*> twod[] = {
      {"manhattan3500", "isam/manhattanOlson3500.txt"},
      {"manhattan3500", "se-sync/manhattan.g2o"},
      {"manhattan3500", "vertigo/originalDataset/g2o/manhattanOlson3500.g2o"},
      {"city10000", "se-sync/city10000.g2o"},
      {"cityTrees10000", "isam/cityTrees10000.txt"},
      {"intel", "se-sync/intel.g2o"},
      {"intel", "vertigo/originalDataset/intel.g2o"},
  };
  for (const auto& [name, path] : twod) {
    CAPTURE(path);
    const PoseGraph2D g = read_pose_graph_2d(data(name, path));
    if (g.landmark_measurements.empty()) {
      const PoseGraph2D back =
          round_trip([&](auto& s) { write_g2o(g, s); }, [](auto& in) { return read_g2o_2d(in, "mem.g2o"); });
      CHECK_MESSAGE(graph_difference(g, back, 1e-13).empty(), graph_difference(g, back, 1e-13));
    }
    // iSAM text keeps no vertices: the poses of the reread graph are the chained odometry.
    PoseGraph2D back =
        round_trip([&](auto& s) { write_isam(g, s); }, [](auto& in) { return read_isam_2d(in, "mem.txt"); });
    PoseGraph2D expected = g;
    if (g.has_initial_poses) expected.poses = back.poses;
    CHECK_MESSAGE(graph_difference(expected, back, 1e-10).empty(), graph_difference(expected, back, 1e-10));
  }
  const std::pair<const char*, const char*> threed[] = {
      {"sphere2500", "isam/sphere2500.txt"},
      {"sphere2500", "se-sync/sphere2500.g2o"},
      {"parking-garage", "se-sync/parking-garage.g2o"},
  };
  for (const auto& [name, path] : threed) {
    CAPTURE(path);
    const PoseGraph3D g = read_pose_graph_3d(data(name, path));
    const PoseGraph3D from_g2o =
        round_trip([&](auto& s) { write_g2o(g, s); }, [](auto& in) { return read_g2o_3d(in, "mem.g2o"); });
    CHECK_MESSAGE(graph_difference(g, from_g2o, 1e-13).empty(), graph_difference(g, from_g2o, 1e-13));
    const PoseGraph3D from_isam =
        round_trip([&](auto& s) { write_isam(g, s); }, [](auto& in) { return read_isam_3d(in, "mem.txt"); });
    PoseGraph3D expected = g;
    if (g.has_initial_poses) expected.poses = from_isam.poses;
    CHECK_MESSAGE(graph_difference(expected, from_isam, 1e-10).empty(),
                  graph_difference(expected, from_isam, 1e-10));
  }
  // Cross-format: the iSAM Manhattan file written as g2o and read back is the same graph.
  const PoseGraph2D m = read_isam_2d(data("manhattan3500", "isam/manhattanOlson3500.txt"));
  const PoseGraph2D back = round_trip_file(
      "keel_graph_manhattan_roundtrip.g2o", [&](const fs::path& f) { write_pose_graph(m, f); },
      [](const fs::path& f) { return read_pose_graph_2d(f); });
  CHECK(graph_difference(m, back, 1e-13).empty());
}

TEST_CASE("the iSAM numbers are square-root information: whitened noise has unit spread" *
          doctest::test_suite("datasets")) {
  // Manhattan3500: 44.72 = √2000 on every axis; noise σ = 0.0224.
  {
    const auto noisy = read_isam_2d(data("manhattan3500", "isam/manhattanOlson3500.txt"));
    const auto truth =
        read_isam_2d(data("manhattan3500", "isam/groundtruth/manhattanOlson3500_groundtruth.txt"));
    const NoiseCheck c = edge_noise(noisy, truth);
    check_unit(c.sqrt_reading, 0.05);
    check_far(c.information_reading);
    // The vertigo g2o copy carries the same numbers in the information slot: read by the g2o reader, its
    // noise model is off by the same factor (spread ≈ 0.15).
    const auto g2o = read_g2o_2d(data("manhattan3500", "vertigo/originalDataset/g2o/manhattanOlson3500.g2o"));
    Spread s(3);
    for (std::size_t k = 0; k < g2o.edges.size(); ++k) {
      s.add(whiten<3>(g2o.edges[k].information,
                      rho(truth.edges[k].measurement.inverse() * g2o.edges[k].measurement)));
    }
    for (int k = 0; k < 3; ++k) CHECK(s.std(k) < 0.2);
  }
  // City10000: 50 0 0 50 0 100 -> σ = (0.02, 0.02, 0.01).
  {
    const auto noisy = read_isam_2d(data("city10000", "isam/city10000.txt"));
    const auto truth = read_isam_2d(data("city10000", "isam/groundtruth/city10000_groundtruth.txt"));
    const NoiseCheck c = edge_noise(noisy, truth);
    check_unit(c.sqrt_reading, 0.05);
    check_far(c.information_reading);
  }
  // CityTrees10000: odometry as City10000, landmarks 10 0 10 -> σ = 0.1.
  {
    const auto noisy = read_isam_2d(data("cityTrees10000", "isam/cityTrees10000.txt"));
    const auto truth =
        read_isam_2d(data("cityTrees10000", "isam/groundtruth/cityTrees10000_groundtruth.txt"));
    const NoiseCheck c = edge_noise(noisy, truth);
    check_unit(c.sqrt_reading, 0.05);
    check_far(c.information_reading);
    REQUIRE(noisy.landmark_measurements.size() == truth.landmark_measurements.size());
    Spread right(2), wrong(2);
    for (std::size_t k = 0; k < noisy.landmark_measurements.size(); ++k) {
      const auto& m = noisy.landmark_measurements[k];
      const auto& t = truth.landmark_measurements[k];
      REQUIRE(m.pose == t.pose);
      REQUIRE(m.landmark == t.landmark);
      const Vec2 r = m.position - t.position;
      right.add(whiten<2>(m.information, r));
      wrong.add(whiten<2>(numbers_read_as_information<2>(m.information), r));
    }
    check_unit({right.std(0), right.std(1)}, 0.05);
    check_far({wrong.std(0), wrong.std(1)});
  }
  // sphere2500: diag 10, 10, 10, 100, 100, 25 over (x, y, z, roll, pitch, yaw), taken as (t, φ).
  {
    const auto noisy = read_isam_3d(data("sphere2500", "isam/sphere2500.txt"));
    const auto truth = read_isam_3d(data("sphere2500", "isam/groundtruth/sphere2500_groundtruth.txt"));
    const NoiseCheck c = edge_noise(noisy, truth);
    check_unit(c.sqrt_reading, 0.05);
    check_far(c.information_reading);
  }
}

TEST_CASE("ground-truth chaining reproduces the derived files" * doctest::test_suite("datasets")) {
  const GroundTruthOptions grid{.translation_step = 0.5, .angle_step = 0.5 * kPi};
  const std::pair<const char*, std::pair<const char*, const char*>> grids[] = {
      {"manhattan3500",
       {"isam/groundtruth/manhattanOlson3500_groundtruth.txt",
        "derived/manhattanOlson3500_groundtruth_poses.txt"}},
      {"city10000",
       {"isam/groundtruth/city10000_groundtruth.txt", "derived/city10000_groundtruth_poses.txt"}},
      {"cityTrees10000",
       {"isam/groundtruth/cityTrees10000_groundtruth.txt", "derived/cityTrees10000_groundtruth_poses.txt"}},
  };
  for (const auto& [name_c, files] : grids) {
    const std::string name = name_c;
    CAPTURE(name);
    const GroundTruth2D gt = read_isam_ground_truth_2d(data(name, files.first), grid);
    const auto derived = read_poses_2d(data(name, files.second));
    REQUIRE(gt.poses.size() == derived.size());
    double worst = 0.0;
    for (std::size_t k = 0; k < derived.size(); ++k) {
      worst = std::max(worst, (gt.poses[k].matrix() - derived[k].matrix()).cwiseAbs().maxCoeff());
    }
    CHECK(worst < 1e-15);
    CHECK(gt.max_edge_translation_error < 1e-12);  // every loop closure agrees exactly
    CHECK(gt.max_edge_rotation_error < 1e-12);
    // Without snapping the chain drifts (6-digit printing), as SOURCE.md says: loop closures disagree a
    // little (CityTrees10000 has no pose-pose loop closures, so its chain is trivially consistent).
    const GroundTruth2D loose = read_isam_ground_truth_2d(data(name, files.first));
    if (name != "cityTrees10000") CHECK(loose.max_edge_translation_error > 1e-4);
    CHECK(loose.max_edge_translation_error < 0.05);
  }
  const GroundTruth2D trees = read_isam_ground_truth_2d(
      data("cityTrees10000", "isam/groundtruth/cityTrees10000_groundtruth.txt"), grid);
  const auto landmarks =
      read_landmarks_2d(data("cityTrees10000", "derived/cityTrees10000_groundtruth_landmarks.txt"));
  REQUIRE(trees.landmarks.size() == landmarks.size());
  for (std::size_t k = 0; k < landmarks.size(); ++k) CHECK(trees.landmarks[k] == landmarks[k]);
  CHECK(trees.max_landmark_error < 1e-12);  // all 4443 observations agree

  // Vertigo's absolute ground truth agrees with the derived poses to print precision (3.7e-6).
  const auto vertigo = read_pose_list_2d(
      data("manhattan3500", "vertigo/groundTruth/manhattanOlson3500_nodes_groundTruth.dat"));
  const auto derived =
      read_poses_2d(data("manhattan3500", "derived/manhattanOlson3500_groundtruth_poses.txt"));
  REQUIRE(vertigo.size() == derived.size());
  for (std::size_t k = 0; k < derived.size(); ++k) CHECK(vertigo[k].is_approx(derived[k], 1e-5));

  // sphere2500: chained in floating point, printed with 9 decimals.
  const GroundTruth3D sphere =
      read_isam_ground_truth_3d(data("sphere2500", "isam/groundtruth/sphere2500_groundtruth.txt"));
  const auto sphere_derived = read_poses_3d(data("sphere2500", "derived/sphere2500_groundtruth_poses.txt"));
  REQUIRE(sphere.poses.size() == sphere_derived.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < sphere_derived.size(); ++k) {
    worst = std::max(worst, (sphere.poses[k].matrix() - sphere_derived[k].matrix()).cwiseAbs().maxCoeff());
  }
  CHECK(worst < 5e-9);
  CHECK(sphere.max_edge_translation_error < 2.5e-4);  // SOURCE.md: 2.3e-4 and 4.3e-6 rad (print rounding)
  CHECK(sphere.max_edge_rotation_error < 5e-6);
}

TEST_CASE("resolver: search order, sha256 verification and the error text" *
          doctest::test_suite("datasets")) {
  const fs::path tmp = fs::temp_directory_path() / "keel_resolver_test";
  fs::remove_all(tmp);
  fs::create_directories(tmp / "repo" / "datasets");
  fs::copy_file(source_root() / "datasets" / "manifest.toml", tmp / "repo" / "datasets" / "manifest.toml");
  const std::string name = "intel", path = "vertigo/originalDataset/intel.g2o";
  const char* old_env = std::getenv("KEEL_DATASETS");
  const std::string saved = old_env ? old_env : "";
  unsetenv("KEEL_DATASETS");

  // Nothing anywhere: the message lists every place and how to fetch.
  std::string msg;
  try {
    resolve_dataset_file(name, path, tmp / "repo");
  } catch (const DatasetError& e) {
    msg = e.what();
  }
  CHECK(msg.find("$KEEL_DATASETS/intel/vertigo/originalDataset/intel.g2o: KEEL_DATASETS is not set") !=
        std::string::npos);
  CHECK(msg.find((tmp / "repo" / "datasets" / "cache" / name / path).string() + ": not found") !=
        std::string::npos);
  CHECK(msg.find((tmp / "shared" / "datasets" / name / path).string() + ": not found") != std::string::npos);
  CHECK(msg.find("scripts/fetch-datasets intel") != std::string::npos);

  // A corrupted copy under KEEL_DATASETS is rejected (same size, one byte changed), a good one in the cache
  // is used.
  const fs::path good = data(name, path);
  fs::create_directories((tmp / "env" / name / path).parent_path());
  fs::copy_file(good, tmp / "env" / name / path);
  {
    std::fstream f(tmp / "env" / name / path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('#');
  }
  setenv("KEEL_DATASETS", (tmp / "env").c_str(), 1);
  try {
    resolve_dataset_file(name, path, tmp / "repo");
    CHECK_MESSAGE(false, "expected a DatasetError");
  } catch (const DatasetError& e) {
    msg = e.what();
  }
  CHECK(msg.find((tmp / "env" / name / path).string() + ": sha256 ") != std::string::npos);
  CHECK(msg.find("differs from the manifest's 4d87aaf96e1e04e4") != std::string::npos);
  fs::create_directories((tmp / "repo" / "datasets" / "cache" / name / path).parent_path());
  fs::copy_file(good, tmp / "repo" / "datasets" / "cache" / name / path);
  CHECK(resolve_dataset_file(name, path, tmp / "repo") == tmp / "repo" / "datasets" / "cache" / name / path);
  // The repo root is found from a subfolder.
  fs::create_directories(tmp / "repo" / "a" / "b");
  CHECK(find_repo_root(tmp / "repo" / "a" / "b") == tmp / "repo");
  // Unknown names list what exists.
  try {
    resolve_dataset_file(name, "nope.g2o", tmp / "repo");
  } catch (const DatasetError& e) {
    msg = e.what();
  }
  CHECK(msg.find("dataset 'intel' has no file 'nope.g2o'") != std::string::npos);
  CHECK(msg.find("se-sync/intel.g2o") != std::string::npos);
  try {
    resolve_dataset_file("nope", "x", tmp / "repo");
  } catch (const DatasetError& e) {
    msg = e.what();
  }
  CHECK(msg.find("no dataset named 'nope' (known: ") != std::string::npos);

  if (old_env) {
    setenv("KEEL_DATASETS", saved.c_str(), 1);
  } else {
    unsetenv("KEEL_DATASETS");
  }
  fs::remove_all(tmp);
}

TEST_CASE("manifest parsing is strict") {
  const fs::path tmp = fs::temp_directory_path() / "keel_manifest_test.toml";
  auto error_for = [&](const std::string& text) {
    std::ofstream(tmp) << text;
    try {
      load_dataset_manifest(tmp);
    } catch (const DatasetError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string head =
      "version = 1\n[datasets.x]\ntitle = \"t\"\ncitation = \"c\"\n[datasets.x.files.\"a.txt\"]\n";
  const std::string good_file = "sha256 = \"" + std::string(64, 'a') +
                                "\"\nbytes = 1\nrepository = \"o/r\"\ncommit = \"c\"\nsource_path = \"a\"\n"
                                "git_blob = \"b\"\nlicense = \"l\"\n";
  CHECK(error_for(head + good_file) == "(no error)");
  CHECK(error_for(head + good_file + "colour = \"red\"\n").find("key 'colour' (line 13): unknown key") !=
        std::string::npos);
  CHECK(error_for(head + "sha256 = \"abc\"\n" + good_file.substr(good_file.find("bytes")))
            .find("expected 64 lower-case hex digits") != std::string::npos);
  CHECK(
      error_for("version = 1\n[datasets.x]\ntitle = \"t\"\ncitation = \"c\"\n[datasets.x.files.\"../a\"]\n" +
                good_file)
          .find("must be relative") != std::string::npos);
  // A file a Debian package installs: its own keys, an absolute path, and no repository keys beside them.
  const std::string installed = "sha256 = \"" + std::string(64, 'a') +
                                "\"\nbytes = 1\ndebian_package = \"p\"\npackage_version = \"1\"\n"
                                "system_path = \"/usr/share/p/a\"\ngit_blob = \"b\"\nlicense = \"l\"\n";
  CHECK(error_for(head + installed) == "(no error)");
  CHECK(error_for(head + installed.substr(0, installed.find("system_path")) + "system_path = \"share/a\"\n" +
                  installed.substr(installed.find("git_blob")))
            .find("is not an absolute path") != std::string::npos);
  CHECK(error_for(head + installed + "repository = \"o/r\"\n").find("key 'repository'") != std::string::npos);
  std::string unversioned = installed;
  unversioned.erase(unversioned.find("package_version"), std::string("package_version = \"1\"\n").size());
  CHECK(error_for(head + unversioned).find("package_version") != std::string::npos);
  fs::remove(tmp);
}
