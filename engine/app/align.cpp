#include "app/align.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string_view>

#include "core/names.hpp"
#include "core/parse.hpp"

namespace keel::app {

namespace {

// Splits a CSV line at commas, trimming blanks around every field.
std::vector<std::string_view> fields_of(std::string_view line) {
  std::vector<std::string_view> out = core::split_fields(line, ',');
  for (auto& f : out) {
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t' || f.front() == '\r')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
  }
  return out;
}

// A header field begins with a letter or '_' (after an optional '"') and is no spelling of NaN or infinity,
// so that "nan", "inf", "1O" or "-x" can never make a data row into a header.
bool header_field(std::string_view f) {
  if (!f.empty() && f.front() == '"') f.remove_prefix(1);
  if (f.empty()) return false;
  const auto c = static_cast<unsigned char>(f.front());
  if (!(std::isalpha(c) || c == '_')) return false;
  std::string lower(f);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  while (!lower.empty() && lower.back() == '"') lower.pop_back();
  return lower != "nan" && lower != "inf" && lower != "infinity" && lower.rfind("nan(", 0) != 0;
}

constexpr core::NameTable<Dissimilarity, 2> kDissimilarities{
    "app::Dissimilarity",
    {{{Dissimilarity::standardized, "standardized"}, {Dissimilarity::euclidean, "euclidean"}}}};

}  // namespace

std::string_view to_string(Dissimilarity d) { return kDissimilarities.name(d); }
Dissimilarity dissimilarity_from_string(std::string_view text) { return kDissimilarities.parse(text); }

Survey read_survey_csv(const std::filesystem::path& file, bool has_depth) {
  // Read once (a pipe or FIFO works), then parse from memory.
  std::string text;
  if (auto why = core::read_whole_file(file, text); !why.empty())
    throw std::invalid_argument(fmt::format("{}: the survey file: {}", file.string(), why));
  std::string_view rest = text;
  if (rest.starts_with("\xEF\xBB\xBF")) rest.remove_prefix(3);  // a UTF-8 byte-order mark
  Survey s;
  s.name = file.string();
  const std::size_t lead = has_depth ? 3 : 2;
  std::size_t columns = 0;
  int number = 0;
  bool first_record = true;
  for (const std::string_view line : core::split_fields(rest, '\n')) {
    ++number;
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string_view::npos || line[b] == '#') continue;
    const std::vector<std::string_view> f = fields_of(line);
    if (first_record) {
      first_record = false;
      // The header rule: only the first record can be a header, and only when every field is a name (see
      // header_field); any other line must be all numbers, or it is an error at its line and column.
      if (std::all_of(f.begin(), f.end(), header_field)) continue;
    }
    if (columns == 0) {
      columns = f.size();
      if (columns < lead + 1)
        throw std::invalid_argument(
            fmt::format("{}:{}: {} columns; need x, y{} and at least one feature column", s.name, number,
                        columns, has_depth ? ", depth" : ""));
      s.dim = static_cast<int>(columns - lead);
    }
    if (f.size() != columns)
      throw std::invalid_argument(
          fmt::format("{}:{}: {} columns where the first record has {}", s.name, number, f.size(), columns));
    for (std::size_t k = 0; k < columns; ++k) {
      double v = 0.0;
      if (auto why = core::parse_real(f[k], v); !why.empty())
        throw std::invalid_argument(fmt::format("{}:{}: column {}: {}", s.name, number, k + 1, why));
      if (k == 0)
        s.x.push_back(v);
      else if (k == 1)
        s.y.push_back(v);
      else if (k == 2 && has_depth)
        s.z.push_back(v);
      else
        s.features.push_back(v);
    }
  }
  if (s.x.empty()) throw std::invalid_argument(fmt::format("{}: no position in the file", s.name));
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
