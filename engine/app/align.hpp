// keel::app — trajectory alignment without data association (thesis ch. 3) on a user's surveys, shared by
// `keel align` and Python's keel.align, so that the same inputs give bit-identical transforms everywhere:
//   read_survey_csv / write_survey_csv   a survey as plain CSV: x, y[, depth], then the feature columns;
//   align_surveys                        the dissimilarity C_ij, keel.align's methods and shrinking rounds,
//   and
//                                        (optionally) the certified optimum over SO(2) of round 0's
//                                        objective;
//   write_alignment_world                a simulated survey pair (sim::make_alignment_world, the worlds of
//                                        ch3_table3_1_alignment) written as the CSV files align_surveys
//                                        reads;
//   write_terrain_world                  the same for a survey pair over a real elevation grid
//                                        (sim::make_terrain_world, the worlds of ch3_table3_1_terrain_*).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "align/align.hpp"
#include "align/certificate.hpp"
#include "sim/alignment_world.hpp"
#include "sim/terrain.hpp"

namespace keel::app {

/// One survey: positions (m), optional depths, and `dim` feature values per position (row-major).
struct Survey {
  std::vector<double> x, y, z;  // z empty: planar
  std::vector<double> features;
  int dim = 0;
  std::string name;  // the file it came from (messages)
  [[nodiscard]] std::size_t size() const { return x.size(); }
};

/// Reads a survey: one position per line, comma-separated `x, y[, depth], f1, …, fk` (`depth` when
/// `has_depth`), every line the same number of columns, at least one feature column; a UTF-8 byte-order mark
/// is dropped, blank lines and lines starting with '#' are skipped. The header rule: the first record is a
/// header when every field begins with a letter or '_' (after an optional '"') and none spells NaN or
/// infinity; every other record is data. Numbers go through core::parse_real (subnormals accepted; inf, nan,
/// overflow and trailing junk refused). Throws std::invalid_argument naming file, line and column for an
/// unreadable file, a value that is not a finite number, a line with another column count, or no position.
[[nodiscard]] Survey read_survey_csv(const std::filesystem::path& file, bool has_depth = false);
/// Writes a survey in that format with a header line, every value to 17 significant digits (read back
/// bit for bit).
void write_survey_csv(const Survey& survey, const std::filesystem::path& file);

enum class Dissimilarity {
  standardized,  // Euclidean distance after dividing every feature column by its std over the reference
  euclidean,  // Euclidean distance of the raw feature vectors (the dissimilarity of ch3_table3_1_alignment)
};
[[nodiscard]] std::string_view to_string(Dissimilarity d);
[[nodiscard]] Dissimilarity dissimilarity_from_string(std::string_view text);  // throws std::invalid_argument

/// The options of `keel align` and keel.align: keel.align's defaults (the schedule and LP settings of
/// ch3_table3_1_alignment) with these fields exposed.
struct AlignSurveysOptions {
  align::Method method = align::Method::proposed;
  Dissimilarity dissimilarity = Dissimilarity::standardized;
  align::RegionOptions region;   // the shrinking rounds
  double depth_gate = 0.0;       // γ of §3.4.3 (m) when both surveys carry depths; 0: no gate
  double disc_tolerance = 1e-6;  // so_conv_hull's tangent cuts
  double matrix_bound = 10.0;    // |entries of A| bound of the LPs
  bool certify = false;          // also certify the optimum over SO(2) of round 0's objective (planar only)
  align::CertificateOptions certificate;
  unsigned threads = 1;   // hulls and sectors (the result does not depend on it); 0: all cores
  void validate() const;  // throws std::invalid_argument naming the field
};

struct SurveyAlignment {
  align::AlignResult result;  // transform (raw and rigid), cost, every round's estimate
  std::optional<align::Certificate> certificate;
  std::size_t reference_points = 0, query_points = 0;
};

/// Aligns `query` to `reference`: p_ref = A p_query + t (eq. 3.1). Throws std::invalid_argument for
/// surveys of different feature dimension, depths on one survey only, a gate without depths, too few
/// points, or a query outside the reference (align::AlignmentProblem::validate, with the file names).
[[nodiscard]] SurveyAlignment align_surveys(const Survey& reference, const Survey& query,
                                            const AlignSurveysOptions& options = {});

/// The alignment problem align_surveys solves (for tests and for callers that want the C matrix).
[[nodiscard]] align::AlignmentProblem survey_problem(const Survey& reference, const Survey& query,
                                                     Dissimilarity dissimilarity);

/// The ground truth of a written world: p_ref = R(theta) p_query + (tx, ty).
struct WorldTruth {
  double theta = 0, tx = 0, ty = 0;
};
/// Writes world `index` of sim::make_alignment_world(options, seed, index) into `dir` (created if missing):
/// reference.csv and query.csv (write_survey_csv) and truth.csv (theta, tx, ty). With the options, seed and
/// index of a ch3_table3_1_alignment world, `align_surveys` with Dissimilarity::euclidean and that
/// experiment's schedule returns the experiment's transform bit for bit.
WorldTruth write_alignment_world(const sim::AlignmentWorldOptions& options, std::uint64_t seed,
                                 std::uint64_t index, const std::filesystem::path& dir);

/// A written terrain world: its truth (in length units) and where it lies on the grid.
struct TerrainWorldTruth {
  WorldTruth truth;
  double centre_x = 0, centre_y = 0;  // the reference square's centre on the grid (m)
  double roughness = 0;               // elevation RMS about its plane under the query (m)
};
/// Writes world `index` of sim::make_terrain_world(field, options, seed, index) into `dir` as
/// write_alignment_world does, positions and truth in length units (sim::to_length_units: metres divided by
/// `length_unit`). With the settings and seed of a ch3_table3_1_terrain_* experiment (length_unit its sample
/// spacing), `align_surveys` with Dissimilarity::euclidean and the default schedule returns that experiment's
/// transform for the world bit for bit.
TerrainWorldTruth write_terrain_world(const sim::TerrainField& field,
                                      const sim::AlignmentWorldOptions& options, std::uint64_t seed,
                                      std::uint64_t index, double length_unit,
                                      const std::filesystem::path& dir);

}  // namespace keel::app
