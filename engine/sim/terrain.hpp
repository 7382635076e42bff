// Real elevation grids as alignment fields (beyond the thesis: the terrain-relative navigation §3.1
// motivates, on real terrain; a substitute for Fig. 3.5's hull data, which are not public): the keel grid
// file in local metres, the features a survey measures on it, and the alignment worlds cut from it.
//
// A terrain world is a Table 3.1 world (alignment_world.hpp: the same lawn-mowers, query placement, random
// transform and noises, drawn from the same sub-streams) whose feature field is a window of the grid: the
// reference square's centre is drawn uniformly where the square fits inside the grid, and the features are
// the elevation, slope and curvature there, standardised over the reference survey.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/alignment_world.hpp"

namespace keel::sim {

// A rectilinear elevation grid in local metres: node (r, c) at (x[c], y[r]), x and y strictly increasing
// (y from south to north), elevation z[r · cols + c] (m).
struct TerrainGrid {
  std::vector<double> x, y;
  std::vector<double> z;
  std::string source;         // the file's `source` line
  double lon0 = 0, lat0 = 0;  // the projection's origin (degrees): the middle of the grid's extent
  [[nodiscard]] std::size_t rows() const { return y.size(); }
  [[nodiscard]] std::size_t cols() const { return x.size(); }
  [[nodiscard]] double at(std::size_t r, std::size_t c) const { return z[r * x.size() + c]; }
};

// The mean Earth radius (m) of the projection below (IUGG R1).
inline constexpr double kEarthRadius = 6371008.8;

// Reads a keel grid file (scripts/fetch-datasets writes them; format in datasets/README.md):
//   keel-grid 1
//   source <text>
//   rows R
//   cols C
//   lon <C longitudes, degrees east, strictly monotonic>
//   lat <R latitudes, degrees north, strictly monotonic>
//   z_units m
//   values
//   <R lines of C elevations (m)>
// Node coordinates are projected to local metres about the middle of the grid's extent (λ0, φ0) by the
// equirectangular projection x = R cos φ0 (λ − λ0), y = R (φ − φ0): the east-west scale is exact on φ0 and
// off by 1 − cos φ / cos φ0 elsewhere (under 2 % over the 2° of the larger grid). Reference and query are
// simulated and scored in the same metres, so this distortion changes the terrain's shape slightly, not the
// alignment problem's consistency. Rows (and columns) are reordered so y (and x) increase. Throws
// graph::ParseError "<file>:<line>: <what>" (a std::runtime_error) for a malformed file: a wrong or missing
// header line, a count that disagrees with rows or cols, a value that is not a finite number, coordinates
// that are not strictly monotonic, fewer than 3 rows or columns.
[[nodiscard]] TerrainGrid read_terrain_grid(const std::filesystem::path& file);
/// The same on a file's text (`name` in messages); read_terrain_grid reads the file once and calls it.
[[nodiscard]] TerrainGrid parse_terrain_grid(std::string text, const std::string& name);

// The features a survey measures at a position, from the grid: elevation z (m), slope |∇z| (m/m) and
// curvature ∇²z (1/m). The derivatives are central differences at the nodes on the (possibly non-uniform)
// spacing — f' ≈ (h₋² f₊ − h₊² f₋ + (h₊² − h₋²) f₀) / (h₋ h₊ (h₋ + h₊)), f'' ≈ 2 (h₋ f₊ − (h₋ + h₊) f₀ +
// h₊ f₋) / (h₋ h₊ (h₋ + h₊)) — copied from the nearest interior node on the border; every feature is then
// bilinear between nodes.
class TerrainField {
 public:
  static constexpr int kDim = 3;
  explicit TerrainField(TerrainGrid grid);  // throws std::invalid_argument for fewer than 3 rows or columns
  [[nodiscard]] const TerrainGrid& grid() const { return grid_; }
  // Whether (x, y) lies inside the nodes' extent.
  [[nodiscard]] bool contains(double x, double y) const;
  // The three features at (x, y) into out[0 .. 3). Throws std::out_of_range outside the grid.
  void value_into(double x, double y, double* out) const;
  // The RMS (m) of the elevation about its least-squares plane over the positions: a local roughness.
  [[nodiscard]] double roughness(const std::vector<double>& x, const std::vector<double>& y) const;

 private:
  TerrainGrid grid_;
  std::vector<double> slope_, curvature_;  // at the nodes, as grid_.z
};

struct TerrainWorld {
  AlignmentWorld world;               // reference frame: the reference square centred on the origin
  double centre_x = 0, centre_y = 0;  // the reference square's centre in the grid's metres
  double roughness = 0;               // TerrainField::roughness over the query's true positions (m)
};

// World `stream` of `seed` on `field`: make_alignment_world(options, seed, stream, ...) with the window of
// the grid as its field. The field sub-stream draws the reference square's centre uniformly where the square
// lies inside the grid (the bump options are unused). options.feature_dim must be TerrainField::kDim. Throws
// std::invalid_argument when the reference square does not fit the grid.
[[nodiscard]] TerrainWorld make_terrain_world(const TerrainField& field, const AlignmentWorldOptions& options,
                                              std::uint64_t seed, std::uint64_t stream);

// The world in length units: every position (reference, query, the query's true positions) and the truth's
// translation divided by `length_unit` (m, > 0); the rotation is unchanged. A terrain world is aligned in
// units of its sample spacing, so the LPs see Table 3.1's numbers and the schedule's lengths keep their
// values.
void to_length_units(AlignmentWorld& world, double length_unit);

}  // namespace keel::sim
