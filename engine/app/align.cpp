#include "app/align.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "core/names.hpp"
#include "core/parse.hpp"

namespace keel::app {

namespace {

constexpr core::NameTable<Dissimilarity, 2> kDissimilarities{
    "app::Dissimilarity",
    {{{Dissimilarity::standardized, "standardized"}, {Dissimilarity::euclidean, "euclidean"}}}};

}  // namespace

std::string_view to_string(Dissimilarity d) { return kDissimilarities.name(d); }
Dissimilarity dissimilarity_from_string(std::string_view text) { return kDissimilarities.parse(text); }

Survey read_survey_csv(const std::filesystem::path& file, bool has_depth) {
  // Read once (a pipe or FIFO works), then parsed from memory by the one CSV reader (core::parse_numeric_csv:
  // BOM, comments, the header rule, located errors).
  std::string text;
  if (auto why = core::read_whole_file(file, text); !why.empty())
    throw std::invalid_argument(fmt::format("{}: the survey file: {}", file.string(), why));
  Survey s;
  s.name = file.string();
  const std::size_t lead = has_depth ? 3 : 2;
  const core::NumericCsv t = core::parse_numeric_csv(
      text, s.name, lead + 1,
      fmt::format("x, y{} and at least one feature column", has_depth ? ", depth" : ""));
  if (t.rows() == 0) throw std::invalid_argument(fmt::format("{}: no position in the file", s.name));
  s.dim = static_cast<int>(t.columns - lead);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const double* row = t.values.data() + r * t.columns;
    s.x.push_back(row[0]);
    s.y.push_back(row[1]);
    if (has_depth) s.z.push_back(row[2]);
    s.features.insert(s.features.end(), row + lead, row + t.columns);
  }
  return s;
}

void write_survey_csv(const Survey& s, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw std::invalid_argument(fmt::format("cannot write '{}'", file.string()));
  const auto d = static_cast<std::size_t>(s.dim);
  out << "x,y" << (s.z.empty() ? "" : ",depth");
  for (std::size_t k = 0; k < d; ++k) out << ",f" << k + 1;
  out << '\n';
  for (std::size_t i = 0; i < s.size(); ++i) {
    out << fmt::format("{:.17g},{:.17g}", s.x[i], s.y[i]);
    if (!s.z.empty()) out << fmt::format(",{:.17g}", s.z[i]);
    for (std::size_t k = 0; k < d; ++k) out << fmt::format(",{:.17g}", s.features[i * d + k]);
    out << '\n';
  }
  if (!out) throw std::runtime_error(fmt::format("writing '{}' failed", file.string()));
}

void AlignSurveysOptions::validate() const {
  region.validate();
  certificate.validate();
  if (!(depth_gate >= 0))
    throw std::invalid_argument(fmt::format("AlignSurveysOptions.depth_gate = {}: must be >= 0", depth_gate));
  if (!(disc_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("AlignSurveysOptions.disc_tolerance = {}: must be > 0", disc_tolerance));
  if (!(matrix_bound > 0))
    throw std::invalid_argument(
        fmt::format("AlignSurveysOptions.matrix_bound = {}: must be > 0", matrix_bound));
}

align::AlignmentProblem survey_problem(const Survey& a, const Survey& b, Dissimilarity dissimilarity) {
  if (a.dim != b.dim || a.dim < 1)
    throw std::invalid_argument(
        fmt::format("{} has {} feature columns, {} has {}: they must match", a.name, a.dim, b.name, b.dim));
  if (a.z.empty() != b.z.empty())
    throw std::invalid_argument(fmt::format("{} {} depths, {} {}: give both or neither", a.name,
                                            a.z.empty() ? "has no" : "has", b.name,
                                            b.z.empty() ? "none" : "has"));
  align::AlignmentProblem p;
  p.ref_x = a.x, p.ref_y = a.y, p.ref_z = a.z;
  p.query_x = b.x, p.query_y = b.y, p.query_z = b.z;
  if (dissimilarity == Dissimilarity::euclidean) {
    p.dissimilarity = align::euclidean_dissimilarity(a.features, b.features, a.dim);
    return p;
  }
  // Standardized: every column divided by its population std over the reference (align::feature_scales), the
  // same scales applied to both surveys.
  const std::vector<double> scale = align::feature_scales(a.features, a.dim);
  p.dissimilarity = align::euclidean_dissimilarity(align::standardize_features(a.features, scale),
                                                   align::standardize_features(b.features, scale), a.dim);
  return p;
}

SurveyAlignment align_surveys(const Survey& reference, const Survey& query, const AlignSurveysOptions& o) {
  o.validate();
  const align::AlignmentProblem p = survey_problem(reference, query, o.dissimilarity);
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("{} against {}: {}", query.name, reference.name, e.what()));
  }
  if (o.depth_gate > 0 && p.ref_z.empty())
    throw std::invalid_argument("AlignSurveysOptions.depth_gate > 0 needs depths on both surveys");
  if (o.certify && !p.ref_z.empty())
    throw std::invalid_argument("the certificate over SO(2) is for planar surveys (no depth columns)");
  align::AlignOptions ao;
  ao.method = o.method;
  ao.region = o.region;
  ao.depth_gate = o.depth_gate;
  ao.disc_tolerance = o.disc_tolerance;
  ao.lp.matrix_bound = o.matrix_bound;
  ao.threads = o.threads;
  SurveyAlignment s;
  s.reference_points = p.reference_size(), s.query_points = p.query_size();
  const align::Regions global = align::global_regions(p, ao);
  s.result = align::align(p, ao, &global);
  if (o.certify) s.certificate = align::certify_rotation(p, global, ao.lp, o.certificate);
  return s;
}

namespace {
// reference.csv, query.csv and truth.csv of a world, every double with 17 significant digits.
WorldTruth write_world(const sim::AlignmentWorld& w, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  Survey a, b;
  a.x = w.ref_x, a.y = w.ref_y, a.features = w.ref_features, a.dim = w.feature_dim;
  b.x = w.query_x, b.y = w.query_y, b.features = w.query_features, b.dim = w.feature_dim;
  write_survey_csv(a, dir / "reference.csv");
  write_survey_csv(b, dir / "query.csv");
  std::ofstream t(dir / "truth.csv");
  t << "theta,tx,ty\n" << fmt::format("{:.17g},{:.17g},{:.17g}\n", w.theta, w.tx, w.ty);
  if (!t) throw std::runtime_error(fmt::format("writing '{}' failed", (dir / "truth.csv").string()));
  return WorldTruth{w.theta, w.tx, w.ty};
}
}  // namespace

WorldTruth write_alignment_world(const sim::AlignmentWorldOptions& options, std::uint64_t seed,
                                 std::uint64_t index, const std::filesystem::path& dir) {
  return write_world(sim::make_alignment_world(options, seed, index), dir);
}

TerrainWorldTruth write_terrain_world(const sim::TerrainField& field,
                                      const sim::AlignmentWorldOptions& options, std::uint64_t seed,
                                      std::uint64_t index, double length_unit,
                                      const std::filesystem::path& dir) {
  sim::TerrainWorld t = sim::make_terrain_world(field, options, seed, index);
  sim::to_length_units(t.world, length_unit);
  return TerrainWorldTruth{write_world(t.world, dir), t.centre_x, t.centre_y, t.roughness};
}

}  // namespace keel::app
