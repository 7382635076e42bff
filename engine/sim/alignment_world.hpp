// The synthetic alignment worlds of thesis §3.7 (Table 3.1, Fig. 3.4): "synthetic worlds with smoothly
// varying feature spaces", a reference and a query lawn-mower trajectory within that space, the query
// "randomly rotated and translated"; "nominal trackline width ... two meters and the feature vector dimension
// was three". The thesis publishes nothing else about the generator; every other choice below is ours
// (experiment README).
//
// Geometry (reference frame a):
//   * the reference lawn-mower covers the square [−L/2, L/2]² (L = reference_size, centred on the origin);
//   * the query lawn-mower covers a square of side query_size placed uniformly at random fully inside it, so
//   the
//     query lies inside the reference's convex hull (the thesis's assumption, §3.9). With query_track_offset
//     the corner is continuous, so the query's tracklines are offset from the reference's by a uniform random
//     fraction of the spacing (the robots do not drive the same lines); without it the corner is snapped to
//     the reference's sampling grid and every true query position is a reference position;
//   * lawn-mower: tracklines parallel to x, track_spacing apart, driven in boustrophedon order, one position
//   every
//     sample_spacing along each line (lawn_mower()).
// Feature field: feature_dim independent components, each a sum of `bumps` isotropic Gaussian bumps (centres
// uniform over the reference square grown by bump_sigma_max on every side, σ uniform in [bump_sigma_min,
// bump_sigma_max], amplitude of random sign and magnitude uniform in [0.5, 1]), then every component rescaled
// so its root-mean-square deviation from its mean over the reference square is 1. Features are the field at
// the TRUE position plus i.i.d. N(0, feature_noise²) per value. Transform: θ uniform in [−max_rotation,
// max_rotation), t uniform in [−max_translation, max_translation]² (eq. 3.1: p_a = R(θ) p_b + t); the query
// is given in frame b, p_b = R(θ)ᵀ (p_a − t), then N(0, position_noise²) is added per coordinate to the
// positions of both trajectories (ground truth stays noiseless).
//
// Deterministic: world (seed, stream) draws from keel::core::Rng::stream(seed, stream), split into
// independent sub-streams for the field, the query placement, the transform, the feature noise and the
// position noise, so changing one noise level leaves the field, the geometry and the other noise of a world
// unchanged.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace keel::sim {

struct AlignmentWorldOptions {
  double reference_size = 60.0;  // side of the square area the reference lawn-mower covers (m), > 0
  double query_size = 24.0;      // side of the square the query lawn-mower covers (m), in (0, reference_size]
  double track_spacing = 2.0;  // trackline spacing of both lawn-mowers (m), thesis "trackline width 2 m", > 0
  double sample_spacing = 1.0;  // along-track spacing of positions (m), > 0
  int feature_dim = 3;          // thesis: 3; in [1, 64]
  int bumps = 40;  // Gaussian bumps per feature component over the reference area (+ margin), >= 1
  double bump_sigma_min = 3.0;  // bump standard deviation range (m): the field's length scale, 0 < min <= max
  double bump_sigma_max = 8.0;
  double feature_noise =
      0.1;  // std of the noise on every feature value of both trajectories (field RMS is 1)
  double position_noise =
      0.0;  // std of Gaussian noise on every position coordinate (m), both trajectories, >= 0
  double max_translation = 30.0;                 // t components uniform in [−max, max] (m), >= 0
  double max_rotation = 3.14159265358979323846;  // θ uniform in [−max, max), in [0, π]
  bool query_random_heading = true;  // query tracklines at a heading ψ ~ U[0, π) (not along the reference's)
  bool query_track_offset = true;    // query corner continuous (tracklines offset by a random fraction of the
                                     // spacing); false: snapped to the reference's sampling grid
  // Throws std::invalid_argument "AlignmentWorldOptions.<field> = <value>: <reason>".
  void validate() const;
};

// The smooth feature field, kept so figures can draw it and tests can take residuals.
struct FeatureField {
  int dim = 0;
  std::vector<double> cx, cy, sigma, amplitude;  // bumps: component k owns bumps [k*per, (k+1)*per)
  int per_component = 0;
  double offset = 0.0;  // constant added to every component (the generator leaves it 0)
  // Noiseless feature vector at (x, y) in the reference frame: offset + Σ a exp(−|p − c|² / (2σ²)) per
  // component.
  [[nodiscard]] std::vector<double> value(double x, double y) const;
  // The same, written to out[0 .. dim).
  void value_into(double x, double y, double* out) const;
};

// Positions of a lawn-mower survey: tracklines along x at y = y0 + k·track_spacing (k = 0 …
// ⌊height/spacing⌋), positions x0 + m·sample_spacing (m = 0 … ⌊width/sample_spacing⌋), even tracks driven
// towards +x, odd ones towards −x. Counts are rounded with a 1e-9 relative tolerance so 60 / 2 gives 31
// tracks.
struct LawnMower {
  std::vector<double> x, y;  // tracks × per_track positions, in driving order
  int tracks = 0;
  int per_track = 0;
};
// Throws std::invalid_argument for a negative or non-finite size or a non-positive spacing.
[[nodiscard]] LawnMower lawn_mower(double x0, double y0, double width, double height, double track_spacing,
                                   double sample_spacing);

struct AlignmentWorld {
  std::vector<double> ref_x, ref_y;  // reference positions, reference frame (n_a)
  std::vector<double> ref_features;  // n_a × feature_dim, row-major (point i's vector at [i*dim, (i+1)*dim))
  std::vector<double> query_x,
      query_y;  // query positions in the QUERY frame (after the random transform) (n_b)
  std::vector<double> query_features;              // n_b × feature_dim, row-major
  std::vector<double> query_true_x, query_true_y;  // the same query positions in the reference frame (truth)
  int feature_dim = 0;
  // Ground truth transform T^{ab} mapping query-frame positions to the reference frame (eq. 3.1):
  // p_ref = R(theta) p_query + (tx, ty). Alignment methods estimate this.
  double theta = 0.0, tx = 0.0, ty = 0.0;
  FeatureField field;
  double query_x0 = 0.0, query_y0 = 0.0;  // corner the query lawn-mower starts from, reference frame
  double query_heading = 0.0;             // ψ of the query's tracklines in the reference frame (0: along x)
};

// World `stream` of experiment `seed` (validates the options).
[[nodiscard]] AlignmentWorld make_alignment_world(const AlignmentWorldOptions& options, std::uint64_t seed,
                                                  std::uint64_t stream);

// The noiseless feature vector at a reference-frame position, written to out[0 .. feature_dim).
using FeatureFunction = std::function<void(double x, double y, double* out)>;
// The same world with another field than the bumps (terrain.hpp): `draw_field(s)` is called once with the
// seed of the world's field sub-stream (the one the bump field draws from) and returns the field over the
// reference square [−L/2, L/2]², which must stay valid while the world is made. The noiseless features are
// standardised per component to zero mean and unit RMS over the reference positions (the query's with the
// same offsets and scales), so feature_noise keeps its meaning of a noise-to-signal ratio;
// AlignmentWorld::field stays empty and the bump options are unused. Throws std::invalid_argument for an
// empty draw_field.
[[nodiscard]] AlignmentWorld make_alignment_world(
    const AlignmentWorldOptions& options, std::uint64_t seed, std::uint64_t stream,
    const std::function<FeatureFunction(std::uint64_t)>& draw_field);

}  // namespace keel::sim
