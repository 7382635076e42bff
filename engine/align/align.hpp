// Trajectory alignment without data association (thesis ch. 3): the public surface of keel.align.
//
// Given reference positions p^a_i, query positions p^b_j (in their own frames) and a dissimilarity C_ij
// between the feature observed at reference point i and at query point j, find the transform T(p) = A p + t
// of eq. 3.1 that places query points where the reference saw similar features (eq. 3.2), without matching
// points. Each query point's dissimilarity is replaced by the lower convex hull of its cloud {(x_i, y_i,
// C_ij)} (eqs. 3.3–3.4), so the objective Σ_j c_j(T(p_j)) is convex in (A, t) and minimised by a linear
// program (eqs. 3.5–3.8). What keeps A a rotation is what distinguishes the methods of Table 3.1:
//   proposed      A = [[c, −s], [s, c]] with Barni's linear approximation of ‖(c, s)‖ = 1 (eqs. 3.13–3.18),
//                 eight sector LPs (each an edge of a regular octagon), the lowest-cost sector kept
//                 (eq. 3.19);
//   so_conv_hull  A = [[c, −s], [s, c]] in conv SO(2), the unit disc c² + s² ≤ 1 (eq. 3.12 with ⪰ 0; kept
//                 by tangent cuts until the disc error is below a tolerance);
//   symmetric     A = [[c, −s], [s, c]] with no norm constraint (a similarity; the thesis does not define
//                 "Symmetric", this is the reading consistent with its Table 3.1 row);
//   affine        A free (Li et al. 2014).
// The region of interest shrinks over rounds as in Li et al. (2014, §4): round 0 uses every reference point
// and the reference's bounding box; each later round centres a box on every query point's current transformed
// position, takes the reference points inside it, and rebuilds that point's hull (see RegionOptions).
//
// The known-depth case (eq. 3.9): when both trajectories carry depths z, the transform rotates about the
// vertical and translates in (x, y) only, and a depth gate γ pairs query point j only with reference points
// whose depth is within γ of z_j (§3.4.3).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <string_view>
#include <vector>

#include "align/hull.hpp"
#include "align/lp.hpp"

namespace keel::align {

struct Regions;

enum class Method { proposed, so_conv_hull, symmetric, affine };
[[nodiscard]] std::string_view to_string(Method m);
[[nodiscard]] Method method_from_string(std::string_view text);  // throws std::invalid_argument

// What to align. Positions are metres; the dissimilarity is any non-negative-or-not finite number per pair.
struct AlignmentProblem {
  std::vector<double> ref_x, ref_y, ref_z;        // reference trajectory (ref_z empty: planar)
  std::vector<double> query_x, query_y, query_z;  // query trajectory in its own frame (query_z iff ref_z)
  std::vector<double> dissimilarity;              // C_ij at [i * n_b + j] (n_a × n_b, row-major)
  [[nodiscard]] std::size_t reference_size() const { return ref_x.size(); }
  [[nodiscard]] std::size_t query_size() const { return query_x.size(); }
  [[nodiscard]] double c(std::size_t i, std::size_t j) const { return dissimilarity[i * query_x.size() + j]; }
  // Throws std::invalid_argument for: fewer than 3 reference points or no query point, mismatched sizes, NaN
  // or infinite positions or dissimilarities, a reference whose positions are collinear, a query whose
  // centroid lies outside the reference's bounding box (the method aligns a query inside the reference,
  // §3.9).
  void validate() const;
};

// The dissimilarity matrix from a callable C(i, j) (the feature-agnostic interface of §3.6.2).
[[nodiscard]] std::vector<double> dissimilarity_matrix(
    std::size_t n_a, std::size_t n_b, const std::function<double(std::size_t, std::size_t)>& c);
// Euclidean distance between feature vectors (row-major, `dim` values per point).
[[nodiscard]] std::vector<double> euclidean_dissimilarity(const std::vector<double>& features_a,
                                                          const std::vector<double>& features_b, int dim);
// The population standard deviation of every feature column (row-major, `dim` values per point) over one
// survey: the scale that standardises features of different units before the Euclidean distance.
[[nodiscard]] std::vector<double> feature_scales(const std::vector<double>& features, int dim);
// Every column k divided by scale[k] (a copy); a column whose scale is zero or not finite is left as it is.
// The same scales (the reference's) go to both surveys, so equal features stay equal.
[[nodiscard]] std::vector<double> standardize_features(std::vector<double> features,
                                                       const std::vector<double>& scale);

struct RegionOptions {
  int max_rounds = 8;           // rounds after round 0 (0: only the global round)
  double shrink = 0.7;          // box half-width of round r is w0 · shrink^r (w0: half the reference's larger
                                // bounding-box side)
  double min_half_width = 3.0;  // rounds stop once the half-width would fall below this (m)
  std::size_t min_points = 10;  // a box holding fewer reference points keeps the point's previous box (LAIC)
  void validate() const;
};

struct AlignOptions {
  Method method = Method::proposed;
  HullOptions hull;
  RegionOptions region;
  LpSettings lp;                 // lazy-row settings (disc_tolerance is set by the method, see below)
  double disc_tolerance = 1e-6;  // so_conv_hull: hypot(c, s) ≤ 1 + this after the tangent cuts
  double depth_gate = 0.0;       // γ of §3.4.3 in metres; 0: no gating (planar problems must keep 0)
  unsigned threads = 1;          // hulls and sectors in parallel; 0: core::default_threads(). The result
                                 // does not depend on it.
  void validate() const;
};

// p_ref = A p_query + t (eq. 3.1).
struct Transform2 {
  double a11 = 1, a12 = 0, a21 = 0, a22 = 1, tx = 0, ty = 0;
};
// A rigid transform: rotation θ, translation t.
struct Rigid2 {
  double theta = 0, tx = 0, ty = 0;
};

struct RoundTrace {
  double half_width = 0;       // box half-width (round 0: the whole reference)
  double cost = 0;             // LP optimum Σ u_j (of the sector kept)
  int sector = -1;             // proposed: sector kept (0–7, sector k spans angles [k, k+1]·45°)
  std::size_t planes = 0;      // hull planes over all query points
  std::size_t plane_rows = 0;  // plane rows the LP ended with (kept sector)
  int solves = 0;              // LP solves this round (all sectors)
  int iterations = 0;          // simplex iterations over those solves
  std::size_t kept_boxes = 0;  // query points whose box stayed (too few reference points)
  double hull_time_s = 0, lp_time_s = 0;
  Transform2 transform;  // the round's estimate (raw)
};

struct AlignResult {
  Method method = Method::proposed;
  Transform2 raw;   // as the LP returned it
  Rigid2 rigid;     // raw projected to SE(2): closest rotation (polar), translation that keeps the query
                    // centroid where raw puts it
  double cost = 0;  // final round's LP optimum
  int sector = -1;  // proposed: final round's sector
  std::vector<RoundTrace> rounds;
  double time_s = 0;
};

// The hulls of later rounds, shared by the methods that align one problem: several methods often put a query
// point's box around the same reference points, and the hull of query point j over one set of reference
// points is the same whichever method asked for it. An entry holds the planes and the seconds their
// computation took; a method that reuses an entry is charged those seconds (RoundTrace::hull_time_s,
// AlignResult::time_s), so each method's time stays what it would be alone. Safe to share between threads;
// one cache per problem and hull options (align() refuses a cache made for other hull options).
class HullCache {
 public:
  struct Entry {
    std::vector<Plane> planes;
    double time_s = 0;  // seconds the planes took to compute
  };
  explicit HullCache(const HullOptions& options) : options_(options) {}
  [[nodiscard]] const HullOptions& options() const { return options_; }
  // The entry of query point j over the reference points `indices` (ascending), or null.
  [[nodiscard]] std::shared_ptr<const Entry> find(std::size_t j,
                                                  const std::vector<std::uint32_t>& indices) const;
  // Stores an entry (the first one stays when two threads computed the same hull) and returns the stored one.
  std::shared_ptr<const Entry> insert(std::size_t j, std::vector<std::uint32_t> indices, Entry entry);
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::size_t hits() const;

 private:
  struct Key {
    std::size_t j;
    std::vector<std::uint32_t> indices;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  HullOptions options_;
  mutable std::mutex mutex_;
  mutable std::size_t hits_ = 0;
  std::unordered_map<Key, std::shared_ptr<const Entry>, KeyHash> entries_;
};

// `global` (optional): round 0's regions computed beforehand by global_regions with the same hull options and
// depth gate (several methods on one problem share them). `cache` (optional): the later rounds' hulls shared
// with the other methods on this problem (HullCache); the result is the same with or without it.
[[nodiscard]] AlignResult align(const AlignmentProblem& problem, const AlignOptions& options,
                                const Regions* global = nullptr, HullCache* cache = nullptr);

// --- pieces, exposed for tests, certificates and figures
// ------------------------------------------------------

// Barni et al. (2000) constants of eq. 3.14 for n = 2: α1 = 1, α2 = √2 − 1, δ = 2 / (1 + √(α1² + α2²)).
inline constexpr double kBarniAlpha1 = 1.0;
inline constexpr double kBarniAlpha2 = 0.41421356237309504880;
inline constexpr double kBarniDelta = 0.96043387010341996525;

// The constraints of sector k (0–7, angles [k, k+1]·45°) of eq. 3.19, sign-aware: σc c ≥ 0, σs s ≥ 0, the
// dominance σp p ≥ σq q of the larger magnitude, and δ(α1 σp p + α2 σq q) = 1 (eq. 3.18). Eq. 3.17 as printed
// ("c ≤ s or s ≤ c") compares signed values and admits |(c, s)| up to ~2.5 in the mixed-sign quadrants; here
// the dominance compares magnitudes. The feasible set is the octagon edge between the vertices at angles 45k°
// and 45(k+1)° (radius 1/δ).
//
// Every sector (and octagon_rows) uses the same 12 rows with the same coefficients — c, s, c − s, c + s and
// the eight edge rows δ(α1 σp p + α2 σq q) — and differs only in their bounds: sector k's edge row is = 1,
// the other seven ≤ 1 (redundant on edge k, which lies in the octagon), unused rows free. Switching sectors
// on one LP then changes bounds only, which keeps the dual simplex's basis dual feasible (a proper warm
// start, and its objective a valid lower bound from the first iteration: what lets align() cut off sectors
// that cannot win).
inline constexpr std::size_t kSectorRowCount = 12;
[[nodiscard]] std::vector<CsRow> sector_rows(int k);
// The filled octagon (convex hull of the eight sector edges): every edge row ≤ 1, the others free. Its LP's
// optimum is a lower bound on every sector's.
[[nodiscard]] std::vector<CsRow> octagon_rows();

// Whether the boxes alone rule out sector k: no A on the octagon edge of sector k and no t place every query
// point j inside its box (lo ≤ A p_j + t ≤ hi). For fixed A a translation exists iff, per axis,
// max_j(lo_j − (A p_j)) ≤ min_j(hi_j − (A p_j)); the excess G(λ) of that inequality is convex and piecewise
// linear along the edge (λ ∈ [0, 1] between its vertices), so its minimum is bracketed by a ternary search
// and bounded below with G's Lipschitz constant. True only when that lower bound exceeds `margin` (metres): a
// sector near the edge of feasibility is left to the LP. A true answer means the sector's LP is infeasible.
[[nodiscard]] bool boxes_exclude_sector(const std::vector<double>& qx, const std::vector<double>& qy,
                                        const std::vector<Box>& boxes, int k, double margin);

// Closest rotation to A (polar projection, any sign of det A) with the translation that keeps `(cx, cy)`
// (query frame) where A, t put it.
[[nodiscard]] Rigid2 project_to_rigid(const Transform2& t, double cx, double cy);
// Singular values of A, largest first.
void singular_values(const Transform2& t, double& s1, double& s2);
// Both singular values within `tolerance` of 1 and det A > 0.
[[nodiscard]] bool approximately_valid(const Transform2& t, double tolerance);

// The region of interest (box) of every query point and the planes of its hull, for given boxes; `kept`
// counts boxes that fell back to `previous` (may be empty: then every box must hold enough points).
struct Regions {
  std::vector<Box> boxes;
  std::vector<std::vector<Plane>> planes;
  std::size_t kept = 0;
  std::size_t plane_count = 0;
};
// Round 0: every query point's box is the reference's bounding box, and its cloud every reference point
// (within the depth gate).
[[nodiscard]] Regions global_regions(const AlignmentProblem& problem, const AlignOptions& options);

}  // namespace keel::align
