#include "cov/information.hpp"

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "core/names.hpp"
#include "lie/so3.hpp"

namespace keel::cov {

namespace {

std::string where(int line) { return line > 0 ? fmt::format(" (source line {})", line) : std::string(); }

}  // namespace

// ---------------------------------------------------------------------------------------------------------------------
// Gauge
// ---------------------------------------------------------------------------------------------------------------------

namespace {

constexpr core::NameTable<Gauge, 2> kGauge{"cov::Gauge",
                                           {{{Gauge::fix_pose, "fix_pose"}, {Gauge::prior, "prior"}}}};

}  // namespace

std::string_view to_string(Gauge g) { return kGauge.name(g); }

Gauge gauge_from_string(std::string_view s) { return kGauge.parse(s); }

void GaugeOptions::validate(int num_poses, int pose_dof) const {
  if (pose < 0 || pose >= num_poses)
    throw std::invalid_argument(fmt::format("GaugeOptions: pose {} is not in [0, {})", pose, num_poses));
  if (kind != Gauge::prior) return;
  if (prior_information.rows() != pose_dof || prior_information.cols() != pose_dof)
    throw std::invalid_argument(fmt::format("GaugeOptions: prior_information must be {}x{} (got {}x{})",
                                            pose_dof, pose_dof, prior_information.rows(),
                                            prior_information.cols()));
  if (!prior_information.allFinite())
    throw std::invalid_argument("GaugeOptions: prior_information has non-finite entries");
  const double asym = (prior_information - prior_information.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-9 * std::max(1.0, prior_information.cwiseAbs().maxCoeff()))
    throw std::invalid_argument("GaugeOptions: prior_information must be symmetric");
  Eigen::LLT<MatX> llt(prior_information);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("GaugeOptions: prior_information must be positive definite");
}

// ---------------------------------------------------------------------------------------------------------------------
// SparseInformation
// ---------------------------------------------------------------------------------------------------------------------

void SparseInformation::check_variable(int v) const {
  if (v < 0 || v >= num_variables())
    throw std::out_of_range(fmt::format("cov: variable {} is not in [0, {}) ({} poses, {} landmarks)", v,
                                        num_variables(), num_poses, num_landmarks));
}

int SparseInformation::variable_of_row(int r) const {
  if (r < 0 || r >= size) throw std::out_of_range(fmt::format("cov: row {} is outside H", r));
  // Offsets increase with the variable id; the one variable a fixed gauge removes (offset −1) is given the
  // offset of the next variable, so the last variable whose offset is ≤ r is never the removed one.
  auto eff = [&](int v) {
    while (v < num_variables() && offset[static_cast<std::size_t>(v)] < 0) ++v;
    return v < num_variables() ? offset[static_cast<std::size_t>(v)] : size;
  };
  int lo = 0, hi = num_variables();  // invariant: eff(lo) <= r < eff(hi) (eff(num_variables()) = size)
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    (eff(mid) <= r ? lo : hi) = mid;
  }
  while (offset[static_cast<std::size_t>(lo)] < 0) ++lo;
  return lo;
}

MatX SparseInformation::dense() const {
  MatX H = MatX::Zero(size, size);
  for (int c = 0; c < size; ++c)
    for (int k = col_start[static_cast<std::size_t>(c)]; k < col_start[static_cast<std::size_t>(c) + 1];
         ++k) {
      const int r = row_index[static_cast<std::size_t>(k)];
      H(r, c) = value[static_cast<std::size_t>(k)];
      H(c, r) = value[static_cast<std::size_t>(k)];
    }
  return H;
}

void SparseInformation::validate() const {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument(fmt::format("SparseInformation: {}", what));
  };
  if (num_poses < 1) fail("no poses");
  if (static_cast<int>(offset.size()) != num_variables()) fail("offset must have one entry per variable");
  if (static_cast<int>(col_start.size()) != size + 1) fail("col_start must have size + 1 entries");
  if (col_start.front() != 0 || col_start.back() != static_cast<int>(row_index.size()) ||
      row_index.size() != value.size())
    fail("col_start / row_index / value sizes disagree");
  int expected = 0;
  for (int v = 0; v < num_variables(); ++v) {
    if (offset[static_cast<std::size_t>(v)] < 0) continue;
    if (offset[static_cast<std::size_t>(v)] != expected) fail("offsets must be contiguous in variable order");
    expected += variable_dim(v);
  }
  if (expected != size) fail("offsets do not add up to size");
  for (int c = 0; c < size; ++c) {
    const int b = col_start[static_cast<std::size_t>(c)], e = col_start[static_cast<std::size_t>(c) + 1];
    if (e < b) fail("col_start must be non-decreasing");
    for (int k = b; k < e; ++k) {
      const int r = row_index[static_cast<std::size_t>(k)];
      if (r < 0 || r > c) fail(fmt::format("row index outside the upper triangle in column {}", c));
      if (k > b && r <= row_index[static_cast<std::size_t>(k) - 1])
        fail(fmt::format("row indices not strictly increasing in column {}", c));
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------------
// Assembly
// ---------------------------------------------------------------------------------------------------------------------

namespace {

// Accumulates dense blocks of H (upper triangle) as scalar triplets; compress() sorts and sums duplicates.
class Assembler {
 public:
  explicit Assembler(SparseInformation& H) : H_(H) {}

  // Adds block M (rows of variable a, columns of variable b) for the pair (a, b); both orders are accepted,
  // the block is stored on the upper side. Variables removed by the gauge are skipped.
  void add(int a, int b, const MatX& M) {
    int oa = H_.offset[static_cast<std::size_t>(a)], ob = H_.offset[static_cast<std::size_t>(b)];
    if (oa < 0 || ob < 0) return;
    const bool swap = oa > ob;
    for (int c = 0; c < M.cols(); ++c)
      for (int r = 0; r < M.rows(); ++r) {
        int row = oa + r, col = ob + c;
        if (swap) std::swap(row, col);
        if (row > col) continue;  // lower half of a diagonal block
        triplets_.emplace_back(col, row, M(r, c));
      }
  }

  void compress() {
    std::sort(triplets_.begin(), triplets_.end(), [](const auto& x, const auto& y) {
      return std::tie(std::get<0>(x), std::get<1>(x)) < std::tie(std::get<0>(y), std::get<1>(y));
    });
    H_.col_start.assign(static_cast<std::size_t>(H_.size) + 1, 0);
    H_.row_index.clear();
    H_.value.clear();
    int last_col = -1, last_row = -1;
    for (const auto& [col, row, v] : triplets_) {
      if (col == last_col && row == last_row) {
        H_.value.back() += v;
        continue;
      }
      H_.row_index.push_back(row);
      H_.value.push_back(v);
      ++H_.col_start[static_cast<std::size_t>(col) + 1];
      last_col = col;
      last_row = row;
    }
    for (int c = 0; c < H_.size; ++c)
      H_.col_start[static_cast<std::size_t>(c) + 1] += H_.col_start[static_cast<std::size_t>(c)];
    triplets_.clear();
    triplets_.shrink_to_fit();
  }

 private:
  SparseInformation& H_;
  std::vector<std::tuple<int, int, double>> triplets_;  // (col, row, value)
};

void layout(SparseInformation& H, int num_poses, int num_landmarks, int pose_dof, const GaugeOptions& gauge) {
  gauge.validate(num_poses, pose_dof);
  H.num_poses = num_poses;
  H.num_landmarks = num_landmarks;
  H.pose_dof = pose_dof;
  H.landmark_dof = 2;
  H.gauge = gauge.kind;
  H.gauge_pose = gauge.pose;
  H.offset.assign(static_cast<std::size_t>(H.num_variables()), -1);
  int next = 0;
  for (int v = 0; v < H.num_variables(); ++v) {
    if (v == gauge.pose && gauge.kind == Gauge::fix_pose) continue;
    H.offset[static_cast<std::size_t>(v)] = next;
    next += H.variable_dim(v);
  }
  H.size = next;
}

void check_pose(int id, int num_poses, const char* what, std::size_t k, int line) {
  if (id < 0 || id >= num_poses)
    throw std::invalid_argument(
        fmt::format("information_matrix: {} {}{} refers to pose {}, but there are {} poses", what, k,
                    where(line), id, num_poses));
}

}  // namespace

namespace {

// The pose–pose edges of a 2D or 3D graph: A_i = −A_j, so H_ii = H_jj = A_jᵀ Ω A_j and H_ij = −A_jᵀ Ω A_j.
template <class Graph, class Pose>
void add_pose_edges(const Graph& g, const std::vector<Pose>& poses, Assembler& A) {
  const int n = static_cast<int>(poses.size());
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    check_pose(e.i, n, "edge", k, e.line);
    check_pose(e.j, n, "edge", k, e.line);
    const auto lin = linearize_edge(e.measurement, poses[static_cast<std::size_t>(e.i)],
                                    poses[static_cast<std::size_t>(e.j)]);
    if (e.i == e.j) continue;  // a self-loop: A_i + A_j = 0, no information
    const auto Hjj = (lin.J_r_xi_j.transpose() * e.information * lin.J_r_xi_j).eval();
    A.add(e.i, e.i, Hjj);
    A.add(e.j, e.j, Hjj);
    A.add(e.i, e.j, (-Hjj).eval());
  }
}

}  // namespace

SparseInformation information_matrix(const PoseGraph2D& g, const std::vector<SE2>& poses,
                                     const std::vector<Vec2>& landmarks, const GaugeOptions& gauge) {
  const int n = static_cast<int>(poses.size());
  if (n == 0) throw std::invalid_argument("information_matrix: no poses");
  if (!g.poses.empty() && g.poses.size() != poses.size())
    throw std::invalid_argument(fmt::format("information_matrix: the graph has {} poses but {} were given",
                                            g.poses.size(), poses.size()));
  int m = static_cast<int>(landmarks.size());
  for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k) {
    const auto& lm = g.landmark_measurements[k];
    check_pose(lm.pose, n, "landmark measurement", k, lm.line);
    if (lm.landmark < 0 || lm.landmark >= m)
      throw std::invalid_argument(
          fmt::format("information_matrix: landmark measurement {}{} refers to landmark {}, "
                      "but {} landmark positions were given",
                      k, where(lm.line), lm.landmark, m));
  }
  SparseInformation H;
  layout(H, n, m, 3, gauge);
  Assembler A(H);
  add_pose_edges(g, poses, A);
  for (const auto& lm : g.landmark_measurements) {
    const auto lin = linearize_landmark(lm.position, poses[static_cast<std::size_t>(lm.pose)],
                                        landmarks[static_cast<std::size_t>(lm.landmark)]);
    const int lv = H.landmark_variable(lm.landmark);
    A.add(lm.pose, lm.pose, lin.J_r_xi.transpose() * lm.information * lin.J_r_xi);
    A.add(lm.pose, lv, lin.J_r_xi.transpose() * lm.information * lin.J_r_l);
    A.add(lv, lv, lin.J_r_l.transpose() * lm.information * lin.J_r_l);
  }
  if (gauge.kind == Gauge::prior) A.add(gauge.pose, gauge.pose, gauge.prior_information);
  A.compress();
  return H;
}

SparseInformation information_matrix(const PoseGraph3D& g, const std::vector<SE3>& poses,
                                     const GaugeOptions& gauge) {
  const int n = static_cast<int>(poses.size());
  if (n == 0) throw std::invalid_argument("information_matrix: no poses");
  if (!g.poses.empty() && g.poses.size() != poses.size())
    throw std::invalid_argument(fmt::format("information_matrix: the graph has {} poses but {} were given",
                                            g.poses.size(), poses.size()));
  SparseInformation H;
  layout(H, n, 0, 6, gauge);
  Assembler A(H);
  add_pose_edges(g, poses, A);
  if (gauge.kind == Gauge::prior) A.add(gauge.pose, gauge.pose, gauge.prior_information);
  A.compress();
  return H;
}

}  // namespace keel::cov
