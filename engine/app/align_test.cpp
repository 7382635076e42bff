// Unit tests of app::align_surveys and its CSV surveys: a world written to files and read back aligns bit for
// bit as the engine aligns the world in memory (the path of ch3_table3_1_alignment's study: round 0's
// regions, then align::align with the same options), the defaults are that experiment's settings, and bad
// files give located errors.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "align/align.hpp"
#include "app/align.hpp"
#include "core/config.hpp"
#include "kit/test_kit.hpp"
#include "sim/alignment_world.hpp"
#include "sim/terrain.hpp"

using namespace keel;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("keel_app_align_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string error_of(const fs::path& file, bool depth = false) {
  return testkit::message_of([&] { (void)app::read_survey_csv(file, depth); });
}

// ch3_table3_1_alignment's world options (its [params]), read from the experiment's config.
sim::AlignmentWorldOptions table_world(const core::ConfigTable& p) {
  sim::AlignmentWorldOptions w;
  w.reference_size = p.number("reference_size"), w.query_size = p.number("query_size");
  w.track_spacing = p.number("track_spacing"), w.sample_spacing = p.number("sample_spacing");
  w.feature_dim = static_cast<int>(p.integer("feature_dim")), w.bumps = static_cast<int>(p.integer("bumps"));
  const auto sigma = p.numbers("bump_sigma");
  w.bump_sigma_min = sigma.at(0), w.bump_sigma_max = sigma.at(1);
  w.feature_noise = p.number("feature_noise"), w.position_noise = p.number("position_noise");
  w.max_translation = p.number("max_translation");
  w.max_rotation = p.number("max_rotation_deg") * 3.14159265358979323846 / 180.0;
  w.query_track_offset = p.boolean("query_track_offset"),
  w.query_random_heading = p.boolean("query_random_heading");
  return w;
}

}  // namespace

TEST_CASE("align_surveys: a Table 3.1 world written to CSV aligns bit for bit as in memory, every method") {
  const auto cfg =
      core::load_toml(fs::path(KEEL_SOURCE_DIR) / "experiments/ch3_table3_1_alignment/experiment.toml");
  const core::ConfigTable p = cfg.table("params");
  // The defaults of app::AlignSurveysOptions are the experiment's schedule and LP settings.
  const app::AlignSurveysOptions defaults;
  CHECK(defaults.region.max_rounds == p.integer("max_rounds"));
  CHECK(defaults.region.shrink == p.number("shrink"));
  CHECK(defaults.region.min_half_width == p.number("min_half_width"));
  CHECK(static_cast<double>(defaults.region.min_points) == p.number("min_points"));
  CHECK(defaults.matrix_bound == p.number("matrix_bound"));
  CHECK(defaults.disc_tolerance == p.number("disc_tolerance"));
  CHECK(align::HullOptions{}.max_slope == p.number("max_slope"));

  const sim::AlignmentWorldOptions wo = table_world(p);
  const auto seed = static_cast<std::uint64_t>(cfg.integer("seed"));
  const std::uint64_t index = 3;
  const fs::path dir = scratch("world");
  const app::WorldTruth truth = app::write_alignment_world(wo, seed, index, dir);
  const sim::AlignmentWorld w = sim::make_alignment_world(wo, seed, index);
  CHECK(truth.theta == w.theta);
  const app::Survey ref = app::read_survey_csv(dir / "reference.csv");
  const app::Survey query = app::read_survey_csv(dir / "query.csv");
  REQUIRE(ref.size() == w.ref_x.size());
  CHECK(ref.features == w.ref_features);  // 17 significant digits: every double read back exactly
  CHECK(query.x == w.query_x);

  // The study's problem (study::ch3::problem_of): raw features, Euclidean distance.
  align::AlignmentProblem direct;
  direct.ref_x = w.ref_x, direct.ref_y = w.ref_y, direct.query_x = w.query_x, direct.query_y = w.query_y;
  direct.dissimilarity = align::euclidean_dissimilarity(w.ref_features, w.query_features, w.feature_dim);
  for (const align::Method m : {align::Method::proposed, align::Method::so_conv_hull,
                                align::Method::symmetric, align::Method::affine}) {
    CAPTURE(align::to_string(m));
    align::AlignOptions ao;
    ao.method = m;
    ao.threads = 1;
    const align::Regions global = align::global_regions(direct, ao);
    const align::AlignResult expected = align::align(direct, ao, &global);
    app::AlignSurveysOptions o;
    o.method = m;
    o.dissimilarity = app::Dissimilarity::euclidean;
    const app::SurveyAlignment got = app::align_surveys(ref, query, o);
    CHECK(got.result.raw.a11 == expected.raw.a11);
    CHECK(got.result.raw.a12 == expected.raw.a12);
    CHECK(got.result.raw.a21 == expected.raw.a21);
    CHECK(got.result.raw.a22 == expected.raw.a22);
    CHECK(got.result.raw.tx == expected.raw.tx);
    CHECK(got.result.raw.ty == expected.raw.ty);
    CHECK(got.result.cost == expected.cost);
    CHECK(got.result.rounds.size() == expected.rounds.size());
  }
  // The standardized dissimilarity is the Euclidean one on features divided by the reference's column stds.
  const align::AlignmentProblem st = app::survey_problem(ref, query, app::Dissimilarity::standardized);
  double s0 = 0, m0 = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) m0 += ref.features[3 * i];
  m0 /= static_cast<double>(ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) s0 += (ref.features[3 * i] - m0) * (ref.features[3 * i] - m0);
  s0 = std::sqrt(s0 / static_cast<double>(ref.size()));
  const align::AlignmentProblem only_first = [&] {
    app::Survey a = ref, b = query;
    a.features.assign(ref.features.size(), 0.0), b.features.assign(query.features.size(), 0.0);
    for (std::size_t i = 0; i < a.size(); ++i) a.features[3 * i] = ref.features[3 * i];
    for (std::size_t j = 0; j < b.size(); ++j) b.features[3 * j] = query.features[3 * j];
    return app::survey_problem(a, b, app::Dissimilarity::standardized);
  }();
  CHECK(only_first.c(5, 7) == doctest::Approx(std::abs(ref.features[15] - query.features[21]) / s0));
  CHECK(st.c(5, 7) > 0);
}

TEST_CASE("read_survey_csv: header, comments, depths; located errors for bad files") {
  const fs::path d = scratch("csv");
  {
    std::ofstream(d / "ok.csv") << "# a survey\nx, y, depth, f1, f2\n0, 0, 5, 1, 2\n\n3, 4, 6, 1.5, -2e-3\n";
    const app::Survey s = app::read_survey_csv(d / "ok.csv", true);
    CHECK(s.size() == 2);
    CHECK(s.dim == 2);
    CHECK(s.z == std::vector<double>{5, 6});
    CHECK(s.features == std::vector<double>{1, 2, 1.5, -2e-3});
    const app::Survey planar = app::read_survey_csv(d / "ok.csv");
    CHECK(planar.dim == 3);
    CHECK(planar.z.empty());
  }
  std::ofstream(d / "nan.csv") << "0,0,1\n1,nan,2\n";
  CHECK(testkit::contains(error_of(d / "nan.csv"), "nan.csv:2: column 2: 'nan' is not a finite number"));
  std::ofstream(d / "ragged.csv") << "0,0,1\n1,1,2,3\n";
  CHECK(
      testkit::contains(error_of(d / "ragged.csv"), "ragged.csv:2: 4 columns where the first record has 3"));
  std::ofstream(d / "narrow.csv") << "0,0\n";
  CHECK(testkit::contains(error_of(d / "narrow.csv"),
                          "narrow.csv:1: 2 columns; need x, y and at least one feature"));
  std::ofstream(d / "empty.csv") << "x,y,f\n# nothing\n";
  CHECK(testkit::contains(error_of(d / "empty.csv"), "empty.csv: no position in the file"));
  CHECK(testkit::contains(error_of(d / "missing.csv"),
                          "missing.csv: the survey file: cannot open file (No such file or directory)"));
  // The header rule: only the first record, and only when every field is a name. A first data row that fails
  // to parse is a located error, never a header that silently drops a point.
  std::ofstream(d / "nanfirst.csv") << "nan,0,1\n1,1,2\n";
  CHECK(testkit::contains(error_of(d / "nanfirst.csv"),
                          "nanfirst.csv:1: column 1: 'nan' is not a finite number"));
  std::ofstream(d / "typo.csv") << "1O,0,1\n1,1,2\n";
  CHECK(testkit::contains(error_of(d / "typo.csv"), "typo.csv:1: column 1: '1O' is not a number"));
  std::ofstream(d / "allnan.csv") << "nan,NaN,inf\n1,1,2\n";
  CHECK(
      testkit::contains(error_of(d / "allnan.csv"), "allnan.csv:1: column 1: 'nan' is not a finite number"));
  std::ofstream(d / "bom.csv") << "\xEF\xBB\xBF" << "5,6,7\n1,1,2\n";  // a UTF-8 byte-order mark
  CHECK(app::read_survey_csv(d / "bom.csv").x == std::vector<double>{5, 1});
  std::ofstream(d / "bomheader.csv") << "\xEF\xBB\xBF" << "x,y,\"f1\"\n5,6,7\n";
  CHECK(app::read_survey_csv(d / "bomheader.csv").x == std::vector<double>{5});
  std::ofstream(d / "sub.csv") << "0,0,1e-310\n";
  CHECK(app::read_survey_csv(d / "sub.csv").features == std::vector<double>{1e-310});
  std::ofstream(d / "late.csv") << "0,0,1\nx,y,f\n";  // a header after the first record is data
  CHECK(testkit::contains(error_of(d / "late.csv"), "late.csv:2: column 1: 'x' is not a number"));
  CHECK(testkit::contains(error_of(d), "csv: the survey file: cannot read: is a directory, not a file"));

  // Surveys that cannot be aligned: another feature count, depths on one side, a query outside the reference.
  app::Survey a, b;
  a.name = "a.csv", b.name = "b.csv";
  a.x = {0, 10, 0, 10}, a.y = {0, 0, 10, 10}, a.features = {1, 2, 3, 4}, a.dim = 1;
  b.x = {0, 50}, b.y = {0, 0}, b.features = {1, 1, 1, 1}, b.dim = 2;
  CHECK(testkit::contains(testkit::message_of([&] { (void)app::align_surveys(a, b); }),
                          "a.csv has 1 feature columns, b.csv has 2"));
  b.features = {1, 1}, b.dim = 1;
  CHECK(testkit::contains(testkit::message_of([&] { (void)app::align_surveys(a, b); }),
                          "b.csv against a.csv: AlignmentProblem: the query spans 50 m"));
  b.z = {1, 1};
  CHECK(testkit::contains(testkit::message_of([&] { (void)app::align_surveys(a, b); }),
                          "give both or neither"));
}

TEST_CASE("write_survey_csv round-trips every double exactly") {
  const fs::path d = scratch("roundtrip");
  app::Survey s;
  s.x = {0.1, -1e-300, 123456.789}, s.y = {1.0 / 3.0, 2.0 / 7.0, -0.0}, s.z = {1e10, -2.5, 3};
  s.features = {std::nextafter(1.0, 2.0), -2.2250738585072014e-308, 6.02214076e23}, s.dim = 1;
  app::write_survey_csv(s, d / "s.csv");
  const app::Survey r = app::read_survey_csv(d / "s.csv", true);
  CHECK(r.x == s.x);
  CHECK(r.y == s.y);
  CHECK(r.z == s.z);
  CHECK(r.features == s.features);
}

TEST_CASE(
    "write_terrain_world: a terrain world written to CSV aligns bit for bit as the experiment's problem") {
  // A synthetic grid (0.001° nodes, hills on a slope) in place of the real ones, which the datasets tests
  // cover.
  const fs::path d = scratch("terrain");
  const fs::path grid = d / "hills.grid";
  {
    std::ofstream out(grid);
    out << "keel-grid 1\nsource test hills\nrows 60\ncols 60\nlon";
    for (int c = 0; c < 60; ++c) out << fmt::format(" {}", 10.0 + 0.001 * c);
    out << "\nlat";
    for (int r = 0; r < 60; ++r) out << fmt::format(" {}", 45.0 + 0.001 * r);
    out << "\nz_units m\nvalues\n";
    for (int r = 0; r < 60; ++r) {
      for (int c = 0; c < 60; ++c)
        out << (c ? " " : "")
            << fmt::format("{}", 300 + 60 * std::sin(0.4 * c) * std::cos(0.3 * r) + 2.0 * r);
      out << '\n';
    }
  }
  const sim::TerrainField field(sim::read_terrain_grid(grid));
  // ch3_table3_1_terrain_jacksboro's geometry: Table 3.1's times 50, aligned in units of 50 m.
  sim::AlignmentWorldOptions wo;
  wo.reference_size = 3000, wo.query_size = 1200, wo.track_spacing = 100, wo.sample_spacing = 50;
  wo.max_translation = 1500, wo.feature_noise = 0.3;
  const double unit = 50;
  const app::TerrainWorldTruth written = app::write_terrain_world(field, wo, 20181022, 2, unit, d / "world");
  sim::TerrainWorld t = sim::make_terrain_world(field, wo, 20181022, 2);
  sim::to_length_units(t.world, unit);
  CHECK(written.truth.tx == t.world.tx);
  CHECK(written.centre_x == t.centre_x);
  CHECK(written.roughness == t.roughness);
  const app::Survey ref = app::read_survey_csv(d / "world" / "reference.csv");
  const app::Survey query = app::read_survey_csv(d / "world" / "query.csv");
  CHECK(ref.x == t.world.ref_x);
  CHECK(query.features == t.world.query_features);
  // The study's problem: positions in length units, raw (standardised over the reference) features,
  // Euclidean.
  align::AlignmentProblem direct;
  direct.ref_x = t.world.ref_x, direct.ref_y = t.world.ref_y;
  direct.query_x = t.world.query_x, direct.query_y = t.world.query_y;
  direct.dissimilarity =
      align::euclidean_dissimilarity(t.world.ref_features, t.world.query_features, t.world.feature_dim);
  align::AlignOptions ao;
  ao.threads = 1;
  const align::Regions global = align::global_regions(direct, ao);
  const align::AlignResult expected = align::align(direct, ao, &global);
  app::AlignSurveysOptions o;
  o.dissimilarity = app::Dissimilarity::euclidean;
  const app::SurveyAlignment got = app::align_surveys(ref, query, o);
  CHECK(got.result.raw.a11 == expected.raw.a11);
  CHECK(got.result.raw.a21 == expected.raw.a21);
  CHECK(got.result.raw.tx == expected.raw.tx);
  CHECK(got.result.raw.ty == expected.raw.ty);
  CHECK(got.result.cost == expected.cost);
  CHECK(got.result.rounds.size() == expected.rounds.size());
}
