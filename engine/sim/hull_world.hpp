// A synthetic substitute for the ship-hull data of thesis §3.8 / Fig. 3.5 (HAUV inspecting the USCGC Spencer;
// the field data are not available). Two HAUV inspection surveys of the same hull bottom; per position the
// vehicle's DVL returns of nearby positions give a local curvature estimate, the low-dimensional feature of
// the alignment ("three position coordinates and three curvature feature values" per position).
//
// Frames: ship frame = reference frame a: x along-ship (forward), y athwartships, z depth below the waterline
// (positive down). The hull bottom is the graph z = D(x, y) (HullSurface):
//
//   D = draft − trim·x − rocker·x²/2                      (trim and longitudinal rocker)
//         − deadrise·(√(y² + r_k²) − r_k)                  (rounded-V keel: depth maximum at y = 0, radius
//         r_k) − bilge_curvature·ℓ²·[sp((y − y_b)/ℓ)² + sp((−y − y_b)/ℓ)²]/2   (bilges from |y| ≈ y_b =
//         bilge_offset,
//                                                        sp = softplus, ℓ = bilge_smoothing: D_yy →
//                                                        −bilge_curvature)
//         + Σ a_k exp(−|p − c_k|²/(2 s_k²))                (plating dents and bulges, random)
//
// Survey: lawn-mowers (lawn_mower(), tracklines along x) in the horizontal plane, the vehicle holding a
// vertical standoff below the hull: z_vehicle = D(x, y) + standoff. The query's rectangle lies uniformly at
// random inside the reference's. The query is then given in its own frame b by the known-depth transform of
// eq. 3.9: p_a = [R(θ) 0; 0 1] p_b + [t; 0] (rotation about the vertical only, depth unchanged); θ, t as in
// AlignmentWorld.
//
// DVL: 4 beams in a Janus configuration, each beam_angle from the upward vertical at azimuths 45°, 135°,
// 225°, 315° from the vehicle's heading (the driving direction of its trackline). Each beam is ray-cast to
// the surface; the range gets N(0, range_noise²); a beam is lost with probability dropout and gated when its
// range exceeds max_range. A return is stored in the vehicle's own frame: (its navigation position) + range ·
// (beam direction).
//
// Features: for each position, the returns of every position of the same survey within feature_radius
// (horizontal, in the survey's own frame) are fitted by least squares with z = a + b u + c v + d u² + e u v +
// f v² (u, v relative to the position); fit_surface_curvature() gives the principal curvatures of that
// quadric at (u, v) = (0, 0). The feature vector is (κ1, κ2, slope) with κ1 >= κ2 in 1/m and slope = |∇z|
// (dimensionless): the rotation-invariant quantities of the fit (the thesis does not define its three
// curvature values; κ1 and κ2 are all a quadric's curvature says, and a third curvature value such as the
// mean would be their average). Curvatures are of the graph z = D with z down: the hull's convex turns (keel,
// bilges) and bulges (depth maxima) have κ < 0, dents pushed in (depth minima) κ > 0.
//
// Deterministic: world (seed, stream) draws from keel::core::Rng::stream(seed, stream), split into
// sub-streams (hull, placement, transform, DVL noise and dropouts, position noise).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace keel::sim {

struct HullSurfaceOptions {
  double draft = 5.0;             // depth of the keel line at x = 0 (m), > 0
  double trim = 0.01;             // depth decreases by trim per metre forward (m/m), finite
  double rocker = 0.002;          // longitudinal curvature of the keel line (1/m), >= 0
  double deadrise = 0.08;         // slope of the bottom away from the keel (m/m), >= 0
  double keel_radius = 1.0;       // rounding of the keel (m), > 0: curvature −deadrise/keel_radius at y = 0
  double bilge_offset = 4.5;      // |y| at which the bilge turn starts (m), >= 0
  double bilge_curvature = 0.25;  // curvature of the bilge turn well past bilge_offset (1/m), >= 0
  double bilge_smoothing = 0.5;   // length over which the bilge turn sets in (m), > 0
  int dents = 25;                 // plating dents/bulges over the survey area + margin, >= 0
  double dent_amplitude_min = 0.03;  // |amplitude| uniform in [min, max] (m), random sign; 0 <= min <= max
  double dent_amplitude_max = 0.12;
  double dent_sigma_min = 0.6;  // dent standard deviation uniform in [min, max] (m); 0 < min <= max
  double dent_sigma_max = 1.5;
  // Throws std::invalid_argument "HullSurfaceOptions.<field> = <value>: <reason>".
  void validate() const;
};

// Principal curvatures of a surface graph z = f(u, v) at one point (from the analytic derivatives or a fit).
struct SurfaceCurvature {
  double kappa1 = 0.0, kappa2 = 0.0;  // principal curvatures, kappa1 >= kappa2 (1/m)
  double mean = 0.0;                  // (kappa1 + kappa2) / 2
  double gaussian = 0.0;              // kappa1 · kappa2
  double slope = 0.0;                 // |∇f|
  int points = 0;                     // returns used by a fit
  bool ok = true;                     // false: a fit had fewer than 6 points or a rank-deficient design
};
// Curvature of the graph at a point from its gradient (fu, fv) and Hessian (fuu, fuv, fvv).
[[nodiscard]] SurfaceCurvature graph_curvature(double fu, double fv, double fuu, double fuv, double fvv);
// Least-squares quadric z = a + b u + c v + d u² + e u v + f v², u = x − cx, v = y − cy, and its curvature at
// (cx, cy). Not ok (curvatures 0, slope from a plane fit when >= 3 points) for fewer than 6 points or a
// rank-deficient design (e.g. points on two lines).
[[nodiscard]] SurfaceCurvature fit_surface_curvature(std::span<const double> x, std::span<const double> y,
                                                     std::span<const double> z, double cx, double cy);

// The hull bottom (ship frame). Kept in the world so figures can draw it.
struct HullSurface {
  HullSurfaceOptions shape;
  std::vector<double> dent_x, dent_y, dent_sigma, dent_amplitude;
  [[nodiscard]] double depth(double x, double y) const;
  // Depth with its gradient (dx, dy) and Hessian (dxx, dxy, dyy); any output pointer may be null.
  double depth(double x, double y, double* dx, double* dy, double* dxx = nullptr, double* dxy = nullptr,
               double* dyy = nullptr) const;
  [[nodiscard]] SurfaceCurvature curvature(double x, double y) const;  // analytic
};

struct DvlOptions {
  double beam_angle = 0.5235987755982988;  // angle of every beam from the vertical (rad), in (0, π/2): 30°
  double range_noise = 0.02;               // std of the range noise (m), >= 0
  double dropout = 0.05;                   // probability that a beam gives no return, in [0, 1)
  double max_range = 6.0;                  // returns beyond this range are gated out (m), > 0
  // Throws std::invalid_argument "DvlOptions.<field> = <value>: <reason>".
  void validate() const;
};

struct HullWorldOptions {
  double reference_length = 36.0;  // reference survey rectangle along x (m), > 0
  double reference_width = 16.0;   // ... along y (m), > 0; the rectangle is centred on the origin
  double query_length = 12.0;      // query survey rectangle (m), in (0, reference_length]
  double query_width = 8.0;        // (m), in (0, reference_width]
  double track_spacing = 1.0;      // trackline spacing of both surveys (m), > 0
  double sample_spacing = 0.5;     // along-track spacing of positions (m), > 0
  bool query_track_offset = true;  // as AlignmentWorldOptions::query_track_offset
  double standoff = 1.5;           // vertical distance of the vehicle below the hull (m), > 0
  double feature_radius = 1.5;     // horizontal radius of the positions whose returns a fit uses (m), > 0
  double position_noise = 0.0;     // std of Gaussian noise on the x and y of every position (m), >= 0
  double max_translation = 10.0;   // t components uniform in [−max, max] (m), >= 0
  double max_rotation = 3.14159265358979323846;  // θ uniform in [−max, max), in [0, π]
  HullSurfaceOptions surface;
  DvlOptions dvl;
  // Throws std::invalid_argument "HullWorldOptions.<field> = <value>: <reason>" (and validates surface, dvl).
  void validate() const;
};

struct HullWorld {
  static constexpr int kFeatureDim = 3;
  std::vector<double> ref_x, ref_y, ref_z;        // reference positions, reference frame (z = depth, m) (n_a)
  std::vector<double> ref_features;               // n_a × 3 row-major: (κ1, κ2, slope)
  std::vector<SurfaceCurvature> ref_fits;         // the full fit per reference position
  std::vector<double> query_x, query_y, query_z;  // query positions in the QUERY frame (z unchanged) (n_b)
  std::vector<double> query_features;             // n_b × 3 row-major
  std::vector<SurfaceCurvature> query_fits;       // the full fit per query position
  std::vector<double> query_true_x, query_true_y;  // query positions in the reference frame (truth)
  int feature_dim = kFeatureDim;
  // Ground truth, as AlignmentWorld: p_ref = R(theta) p_query + (tx, ty), z unchanged (eq. 3.9).
  double theta = 0.0, tx = 0.0, ty = 0.0;
  // DVL returns in each survey's own frame, with the index of the position that measured each.
  std::vector<double> ref_return_x, ref_return_y, ref_return_z;
  std::vector<int> ref_return_owner;
  std::vector<double> query_return_x, query_return_y, query_return_z;
  std::vector<int> query_return_owner;
  HullSurface surface;
  double query_x0 = 0.0, query_y0 = 0.0;  // lower-left corner of the query rectangle, reference frame
};

// World `stream` of experiment `seed` (validates the options).
[[nodiscard]] HullWorld make_hull_world(const HullWorldOptions& options, std::uint64_t seed,
                                        std::uint64_t stream);

}  // namespace keel::sim
