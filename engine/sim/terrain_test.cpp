// Real terrain as an alignment field: the grid file's reader (projection, row order, located errors), the
// features' differences (exact on quadratics), the terrain worlds (determinism, standardisation, the truth),
// and the two real grids of datasets/manifest.toml.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "kit/dataset_files.hpp"
#include "kit/test_kit.hpp"
#include "sim/terrain.hpp"

using namespace keel::sim;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A grid file of z(lon, lat) written with the given (possibly decreasing) coordinates.
fs::path write_grid(const std::string& name, const std::vector<double>& lon, const std::vector<double>& lat,
                    const std::function<double(double, double)>& z, const std::string& extra_header = "") {
  const fs::path file = fs::temp_directory_path() / ("keel_terrain_test_" + name + ".grid");
  std::ofstream out(file);
  out << "keel-grid 1\nsource a test grid\n"
      << extra_header << "rows " << lat.size() << "\ncols " << lon.size() << "\nlon";
  for (double v : lon) out << fmt::format(" {}", v);  // shortest round-trip text
  out << "\nlat";
  for (double v : lat) out << fmt::format(" {}", v);
  out << "\nz_units m\nvalues\n";
  for (double la : lat) {
    for (std::size_t c = 0; c < lon.size(); ++c) out << (c ? " " : "") << fmt::format("{}", z(lon[c], la));
    out << '\n';
  }
  return file;
}

std::string error_of(const fs::path& file) {
  try {
    (void)read_terrain_grid(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("terrain grid: projection about the middle, rows reordered south to north") {
  // Latitudes given north to south (as the Jacksboro DEM), longitudes non-uniform.
  const std::vector<double> lon = {10.0, 10.01, 10.03, 10.04}, lat = {45.03, 45.02, 45.01, 45.0};
  const fs::path file =
      write_grid("order", lon, lat, [](double lo, double la) { return 100 * lo + 1000 * la; });
  const TerrainGrid g = read_terrain_grid(file);
  REQUIRE(g.rows() == 4);
  REQUIRE(g.cols() == 4);
  CHECK(g.lon0 == doctest::Approx(10.02));
  CHECK(g.lat0 == doctest::Approx(45.015));
  const double kx = kEarthRadius * std::cos(45.015 * kPi / 180) * kPi / 180, ky = kEarthRadius * kPi / 180;
  CHECK(g.x[0] == doctest::Approx(kx * (10.0 - 10.02)));
  CHECK(g.x[2] == doctest::Approx(kx * (10.03 - 10.02)));
  CHECK(g.y[0] == doctest::Approx(ky * (45.0 - 45.015)));  // the southern row first
  CHECK(g.y[3] == doctest::Approx(ky * (45.03 - 45.015)));
  CHECK(g.at(0, 0) == doctest::Approx(100 * 10.0 + 1000 * 45.0));
  CHECK(g.at(3, 1) == doctest::Approx(100 * 10.01 + 1000 * 45.03));
  CHECK(g.source == "a test grid");
  fs::remove(file);
}

TEST_CASE(
    "terrain field: differences exact on a quadratic, bilinear between nodes, roughness of a plane is 0") {
  // Non-uniform nodes in both directions; z = a x² + b y² + c x y + linear terms in projected metres.
  const std::vector<double> lon = {10.0, 10.004, 10.01, 10.013, 10.02, 10.03},
                            lat = {45.0, 45.006, 45.01, 45.017, 45.02};
  const double lon0 = 0.5 * (10.0 + 10.03), lat0 = 0.5 * (45.0 + 45.02);
  const double kx = kEarthRadius * std::cos(lat0 * kPi / 180) * kPi / 180, ky = kEarthRadius * kPi / 180;
  const double a = 2e-4, b = -3e-4, c = 1e-4;
  const auto quadratic = [&](double x, double y) {
    return a * x * x + b * y * y + c * x * y + 0.1 * x - 0.2 * y + 50;
  };
  const fs::path file = write_grid("quadratic", lon, lat, [&](double lo, double la) {
    return quadratic(kx * (lo - lon0), ky * (la - lat0));
  });
  const TerrainField f(read_terrain_grid(file));
  const TerrainGrid& g = f.grid();
  for (std::size_t i = 1; i + 1 < g.rows(); ++i)
    for (std::size_t j = 1; j + 1 < g.cols(); ++j) {
      double v[TerrainField::kDim];
      f.value_into(g.x[j], g.y[i], v);
      const double zx = 2 * a * g.x[j] + c * g.y[i] + 0.1, zy = 2 * b * g.y[i] + c * g.x[j] - 0.2;
      CHECK(v[0] == doctest::Approx(quadratic(g.x[j], g.y[i])).epsilon(1e-9));
      CHECK(v[1] == doctest::Approx(std::hypot(zx, zy)).epsilon(1e-7));
      CHECK(v[2] == doctest::Approx(2 * a + 2 * b).epsilon(1e-6));
    }
  // Between nodes every feature is bilinear in the four corners.
  double p[3], c00[3], c10[3], c01[3], c11[3];
  const double u = 0.3, w = 0.8;
  const double x = g.x[2] + u * (g.x[3] - g.x[2]), y = g.y[1] + w * (g.y[2] - g.y[1]);
  f.value_into(x, y, p), f.value_into(g.x[2], g.y[1], c00), f.value_into(g.x[3], g.y[1], c10);
  f.value_into(g.x[2], g.y[2], c01), f.value_into(g.x[3], g.y[2], c11);
  for (int k = 0; k < 3; ++k)
    CHECK(p[k] ==
          doctest::Approx((1 - w) * ((1 - u) * c00[k] + u * c10[k]) + w * ((1 - u) * c01[k] + u * c11[k])));
  CHECK_THROWS_AS(f.value_into(g.x.back() + 1, 0, p), std::out_of_range);
  fs::remove(file);

  // A tilted plane has no roughness; a bump on it does.
  const fs::path plane = write_grid("plane", lon, lat, [&](double lo, double la) { return 3 * lo - 7 * la; });
  const TerrainField fp(read_terrain_grid(plane));
  const std::vector<double> xs = {fp.grid().x[1], fp.grid().x[2], fp.grid().x[3], fp.grid().x[2],
                                  fp.grid().x[4]};
  const std::vector<double> ys = {fp.grid().y[1], fp.grid().y[1], fp.grid().y[2], fp.grid().y[3],
                                  fp.grid().y[3]};
  CHECK(fp.roughness(xs, ys) < 1e-9);
  const fs::path bump = write_grid("bump", lon, lat, [&](double lo, double la) {
    return 3 * lo - 7 * la + (lo == 10.013 && la == 45.01 ? 5.0 : 0.0);
  });
  CHECK(TerrainField(read_terrain_grid(bump)).roughness(xs, ys) > 0.5);
  fs::remove(plane), fs::remove(bump);
}

TEST_CASE("terrain grid: a malformed file is refused at its line") {
  const std::vector<double> lon = {10.0, 10.01, 10.02}, lat = {45.0, 45.01, 45.02};
  const auto flat = [](double, double) { return 1.0; };
  const fs::path good = write_grid("good", lon, lat, flat);
  CHECK(error_of(good) == "(no error)");
  const auto with = [&](const std::string& name, const std::function<std::string(std::string)>& edit) {
    std::ifstream in(good);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const fs::path bad = fs::temp_directory_path() / ("keel_terrain_test_" + name + ".grid");
    std::ofstream(bad) << edit(text);
    const std::string e = error_of(bad);
    fs::remove(bad);
    return e;
  };
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  std::string e = with("header", [&](std::string s) { return replace(s, "keel-grid 1", "keel-grid 2"); });
  CHECK_MESSAGE(e.find(":1: not a keel grid file") != std::string::npos, e);
  e = with("rows", [&](std::string s) { return replace(s, "rows 3", "rows 2"); });
  CHECK_MESSAGE(
      e.find(":3: rows: '2' is too small: expected a node count in 3 … 1073741824") != std::string::npos, e);
  e = with("lon", [&](std::string s) { return replace(s, "lon 10 ", "lon "); });
  CHECK_MESSAGE(e.find(":5: lon values: 2 where 3 were expected") != std::string::npos, e);
  e = with("nan", [&](std::string s) { return replace(s, "values\n1", "values\nnan"); });
  CHECK_MESSAGE(e.find(":9: row 1 value 1: 'nan' is not a finite number") != std::string::npos, e);
  e = with("short", [&](std::string s) { return s.substr(0, s.rfind("1 1 1\n")); });
  CHECK_MESSAGE(e.find("the file ends where a row of values was expected") != std::string::npos, e);
  e = with("order", [&](std::string s) { return replace(s, "lat 45 45.01", "lat 45 44.99"); });
  CHECK_MESSAGE(e.find(":6: the latitudes are not strictly monotonic") != std::string::npos, e);
  CHECK(error_of(fs::temp_directory_path() / "keel_terrain_test_missing.grid").find("cannot open") !=
        std::string::npos);
  // A subnormal depth is a number; a count beyond the limit is refused before anything is allocated.
  e = with("subnormal", [&](std::string s) { return replace(s, "values\n1", "values\n1e-310"); });
  CHECK_MESSAGE(e == "(no error)", e);
  e = with("huge", [&](std::string s) { return replace(s, "rows 3", "rows 99999999999999999999"); });
  CHECK_MESSAGE(e.find(":3: rows: '99999999999999999999' is too large") != std::string::npos, e);
  CHECK(error_of(fs::temp_directory_path()).find("is a directory") != std::string::npos);
  fs::remove(good);
}

TEST_CASE("terrain world: deterministic, standardised over the reference, features at the true positions") {
  // A smooth synthetic terrain on a 0.001° grid (about 79 m × 111 m), 60 × 60 nodes.
  std::vector<double> lon, lat;
  for (int k = 0; k < 60; ++k) lon.push_back(10.0 + 0.001 * k), lat.push_back(45.0 + 0.001 * k);
  const fs::path file = write_grid("world", lon, lat, [](double lo, double la) {
    return 300 + 80 * std::sin(400 * (lo - 10)) * std::cos(300 * (la - 45)) + 2000 * (la - 45);
  });
  const TerrainField field(read_terrain_grid(file));
  AlignmentWorldOptions o;
  o.reference_size = 3000, o.query_size = 1200, o.track_spacing = 100, o.sample_spacing = 50;
  o.max_translation = 1500, o.feature_noise = 0.0;
  const TerrainWorld a = make_terrain_world(field, o, 11, 3), b = make_terrain_world(field, o, 11, 3);
  CHECK(a.world.ref_features == b.world.ref_features);
  CHECK(a.centre_x == b.centre_x);
  CHECK(make_terrain_world(field, o, 11, 4).centre_x != a.centre_x);
  // The reference square lies inside the grid.
  const TerrainGrid& g = field.grid();
  CHECK(a.centre_x - 1500 >= g.x.front());
  CHECK(a.centre_x + 1500 <= g.x.back());
  // Standardised: every component has mean 0 and RMS 1 over the reference.
  const std::size_t na = a.world.ref_x.size(), d = TerrainField::kDim;
  for (std::size_t k = 0; k < d; ++k) {
    double mean = 0, square = 0;
    for (std::size_t i = 0; i < na; ++i) mean += a.world.ref_features[i * d + k];
    mean /= static_cast<double>(na);
    for (std::size_t i = 0; i < na; ++i) square += std::pow(a.world.ref_features[i * d + k] - mean, 2);
    CHECK(mean == doctest::Approx(0).scale(1));
    CHECK(std::sqrt(square / static_cast<double>(na)) == doctest::Approx(1));
  }
  // Without noise, a query feature is the terrain at its true position, with the reference's standardisation:
  // the ratio of differences between two query points matches the terrain's.
  double p0[3], p1[3], r0[3], r1[3];
  field.value_into(a.centre_x + a.world.query_true_x[0], a.centre_y + a.world.query_true_y[0], p0);
  field.value_into(a.centre_x + a.world.query_true_x[7], a.centre_y + a.world.query_true_y[7], p1);
  field.value_into(a.centre_x + a.world.ref_x[0], a.centre_y + a.world.ref_y[0], r0);
  field.value_into(a.centre_x + a.world.ref_x[5], a.centre_y + a.world.ref_y[5], r1);
  for (std::size_t k = 0; k < d; ++k) {
    const double q = a.world.query_features[7 * d + k] - a.world.query_features[k];
    const double r = a.world.ref_features[5 * d + k] - a.world.ref_features[k];
    CHECK(q * (r1[k] - r0[k]) == doctest::Approx(r * (p1[k] - p0[k])).epsilon(1e-9));
  }
  // The truth maps the query's positions to their true places (eq. 3.1).
  const double c = std::cos(a.world.theta), s = std::sin(a.world.theta);
  for (std::size_t j = 0; j < a.world.query_x.size(); j += 50) {
    CHECK(c * a.world.query_x[j] - s * a.world.query_y[j] + a.world.tx ==
          doctest::Approx(a.world.query_true_x[j]));
    CHECK(s * a.world.query_x[j] + c * a.world.query_y[j] + a.world.ty ==
          doctest::Approx(a.world.query_true_y[j]));
  }
  CHECK(a.roughness > 0);
  // A reference square larger than the grid and a feature count other than 3 are refused.
  o.reference_size = 10000;
  CHECK(keel::testkit::message_of([&] { (void)make_terrain_world(field, o, 11, 3); }).find("does not fit") !=
        std::string::npos);
  o.reference_size = 3000, o.feature_dim = 2;
  CHECK(keel::testkit::message_of([&] { (void)make_terrain_world(field, o, 11, 3); }).find("feature_dim") !=
        std::string::npos);
  fs::remove(file);
}

TEST_CASE("real data: the two matplotlib grids read as their sources describe" *
          doctest::test_suite("datasets")) {
  const TerrainGrid dem =
      read_terrain_grid(keel::testkit::dataset_file("matplotlib-terrain", "grids/jacksboro_fault_dem.grid"));
  CHECK(dem.rows() == 344);
  CHECK(dem.cols() == 403);
  const auto [lo, hi] = std::minmax_element(dem.z.begin(), dem.z.end());
  CHECK(*lo == 236);
  CHECK(*hi == 1076);
  // 3" nodes: about 74.5 m east-west at 36.6° N and 92.7 m north-south.
  CHECK((dem.x.back() - dem.x.front()) / 402 == doctest::Approx(74.4).epsilon(0.01));
  CHECK((dem.y.back() - dem.y.front()) / 343 == doctest::Approx(92.66).epsilon(0.01));
  const TerrainGrid topo =
      read_terrain_grid(keel::testkit::dataset_file("matplotlib-terrain", "grids/topobathy.grid"));
  CHECK(topo.rows() == 91);
  CHECK(topo.cols() == 120);
  const auto [tlo, thi] = std::minmax_element(topo.z.begin(), topo.z.end());
  CHECK(*tlo < -1000);  // sea floor
  CHECK(*thi > 2000);   // mountains
  // Rows uniform in Mercator y: the spacing in metres shrinks northward with cos φ, about 4 % over the 2°.
  const double south = topo.y[1] - topo.y[0], north = topo.y[90] - topo.y[89];
  CHECK(south / north ==
        doctest::Approx(std::cos(48.03 * kPi / 180) / std::cos(49.97 * kPi / 180)).epsilon(0.005));
}
