#include "sos/problem.hpp"

#include <fmt/format.h>

#include "sos/eigen_sparse.hpp"
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

namespace keel::sos {

namespace {

using Triplet = Eigen::Triplet<double>;

// The rows of one residual under construction. Pose 0 is the identity: its c is the constant 1, its s, x, y
// the constant 0.
struct RowBuilder {
  const PlanarProblem& p;
  std::vector<Triplet>& triplets;
  std::vector<double>& constants;
  int row = 0;

  void pose_field(int pose, int field, double coef) {  // field 0..3 = c, s, x, y
    if (coef == 0.0) return;
    if (pose == 0) {
      if (field == 0) constants[static_cast<std::size_t>(row)] += coef;
      return;
    }
    triplets.emplace_back(row, 4 * (pose - 1) + field, coef);
  }
  void landmark_field(int landmark, int field, double coef) {
    triplets.emplace_back(row, 4 * (p.poses - 1) + 2 * landmark + field, coef);
  }
  void constant(double v) { constants[static_cast<std::size_t>(row)] += v; }
  void next() {
    ++row;
    constants.push_back(0.0);
  }
};

void check_information(const Eigen::MatrixXd& w, const std::string& what) {
  const double scale = w.cwiseAbs().maxCoeff();
  if (!w.allFinite() || !(scale > 0))
    throw std::invalid_argument(
        fmt::format("sos::planar_problem: {} information is not finite and non-zero", what));
  if ((w - w.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    throw std::invalid_argument(fmt::format("sos::planar_problem: {} information is not symmetric", what));
  Eigen::LLT<Eigen::MatrixXd> llt(w);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument(
        fmt::format("sos::planar_problem: {} information is not positive definite", what));
  for (int r = 0; r < w.rows(); ++r)
    for (int c = 0; c < r; ++c)
      if (std::abs(w(r, c)) > 1e-12 * scale)
        throw std::invalid_argument(fmt::format(
            "sos::planar_problem: {} information has a cross term ({}, {}) = {}; eq. 4.10 weighs each axis "
            "separately and has no form for it",
            what, r, c, w(r, c)));
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  }
  void unite(int a, int b) { parent[static_cast<std::size_t>(find(a))] = find(b); }
};

}  // namespace

PlanarProblem planar_problem(const graph::PoseGraph2D& g) {
  int n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) n = std::max(n, std::max(e.i, e.j) + 1);
  for (const auto& m : g.landmark_measurements) n = std::max(n, m.pose + 1);
  if (n < 2)
    throw std::invalid_argument(fmt::format("sos::planar_problem: {} pose(s); at least 2 are needed", n));
  int nl = 0;
  for (const auto& m : g.landmark_measurements) {
    if (m.landmark < 0)
      throw std::invalid_argument(
          fmt::format("sos::planar_problem: landmark id {} < 0 (line {})", m.landmark, m.line));
    nl = std::max(nl, m.landmark + 1);
  }
  PlanarProblem p;
  p.poses = n;
  p.landmarks = nl;
  // Length scale: RMS distance of the initial poses from pose 0.
  if (g.poses.size() >= 2) {
    const lie::SE2 inv0 = g.poses[0].inverse();
    double s2 = 0.0;
    for (const auto& t : g.poses) s2 += (inv0 * t).translation().squaredNorm();
    p.length_scale = std::max(1.0, std::sqrt(s2 / static_cast<double>(g.poses.size())));
  }
  const double L = p.length_scale;

  std::vector<Triplet> triplets;
  std::vector<double> constants{0.0};
  RowBuilder rb{p, triplets, constants};
  UnionFind uf(n + nl);
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = g.edges[k];
    const std::string what =
        fmt::format("edge {} ({}, {}){}", k, e.i, e.j, e.line > 0 ? fmt::format(" at line {}", e.line) : "");
    if (e.i < 0 || e.j < 0 || e.i == e.j)
      throw std::invalid_argument(fmt::format("sos::planar_problem: {} does not join two poses", what));
    check_information(e.information, what);
    uf.unite(e.i, e.j);
    const double c = e.measurement.so2().cos_angle(), s = e.measurement.so2().sin_angle();
    const double tx = e.measurement.translation().x(), ty = e.measurement.translation().y();
    const double wr = std::sqrt(e.information(2, 2)), wx = std::sqrt(e.information(0, 0)),
                 wy = std::sqrt(e.information(1, 1));
    Term term{e.i - 1, e.j - 1, rb.row, 4};
    // (c_j, s_j) − R_i (c̄, s̄), eq. 4.8–4.9
    rb.pose_field(e.j, 0, wr), rb.pose_field(e.i, 0, -wr * c), rb.pose_field(e.i, 1, wr * s), rb.next();
    rb.pose_field(e.j, 1, wr), rb.pose_field(e.i, 0, -wr * s), rb.pose_field(e.i, 1, -wr * c), rb.next();
    // t_j − t_i − R_i t̄, eq. 4.10 (translations in units of L)
    rb.pose_field(e.j, 2, wx * L), rb.pose_field(e.i, 2, -wx * L), rb.pose_field(e.i, 0, -wx * tx),
        rb.pose_field(e.i, 1, wx * ty), rb.next();
    rb.pose_field(e.j, 3, wy * L), rb.pose_field(e.i, 3, -wy * L), rb.pose_field(e.i, 0, -wy * ty),
        rb.pose_field(e.i, 1, -wy * tx), rb.next();
    p.terms.push_back(term);
  }
  for (std::size_t k = 0; k < g.landmark_measurements.size(); ++k) {
    const auto& m = g.landmark_measurements[k];
    const std::string what = fmt::format("landmark measurement {} (pose {}, landmark {}){}", k, m.pose,
                                         m.landmark, m.line > 0 ? fmt::format(" at line {}", m.line) : "");
    if (m.pose < 0)
      throw std::invalid_argument(fmt::format("sos::planar_problem: {} names a pose < 0", what));
    check_information(m.information, what);
    uf.unite(m.pose, n + m.landmark);
    const double zx = m.position.x(), zy = m.position.y();
    const double wx = std::sqrt(m.information(0, 0)), wy = std::sqrt(m.information(1, 1));
    Term term{m.pose - 1, n - 1 + m.landmark, rb.row, 2};
    // l − t_i − R_i z̄, eq. 4.13
    rb.landmark_field(m.landmark, 0, wx * L), rb.pose_field(m.pose, 2, -wx * L),
        rb.pose_field(m.pose, 0, -wx * zx), rb.pose_field(m.pose, 1, wx * zy), rb.next();
    rb.landmark_field(m.landmark, 1, wy * L), rb.pose_field(m.pose, 3, -wy * L),
        rb.pose_field(m.pose, 0, -wy * zy), rb.pose_field(m.pose, 1, -wy * zx), rb.next();
    p.terms.push_back(term);
  }
  constants.pop_back();  // the row opened after the last residual
  for (int i = 1; i < n; ++i)
    if (uf.find(i) != uf.find(0))
      throw std::invalid_argument(fmt::format(
          "sos::planar_problem: the graph is not connected: pose {} has no path of measurements to pose 0",
          i));
  for (int l = 0; l < nl; ++l)
    if (uf.find(n + l) != uf.find(0))
      throw std::invalid_argument(fmt::format(
          "sos::planar_problem: landmark {} is not connected to pose 0 (no measurement sees it, or only a "
          "disconnected part of the graph does)",
          l));
  p.a.resize(static_cast<Eigen::Index>(constants.size()), p.unknowns());
  p.a.setFromTriplets(triplets.begin(), triplets.end());
  p.r = Eigen::Map<const Eigen::VectorXd>(constants.data(), static_cast<Eigen::Index>(constants.size()));
  return p;
}

double polynomial_cost(const PlanarProblem& p, const Eigen::VectorXd& z) {
  if (z.size() != p.unknowns())
    throw std::invalid_argument(
        fmt::format("sos::polynomial_cost: {} unknowns given, {} expected", z.size(), p.unknowns()));
  return (p.a * z + p.r).squaredNorm();
}

Eigen::VectorXd unknowns_of(const PlanarProblem& p, const std::vector<lie::SE2>& poses,
                            const std::vector<lie::Vec2>& landmarks) {
  if (static_cast<int>(poses.size()) != p.poses || static_cast<int>(landmarks.size()) != p.landmarks)
    throw std::invalid_argument(
        fmt::format("sos::unknowns_of: {} poses and {} landmarks given, the problem has {} and {}",
                    poses.size(), landmarks.size(), p.poses, p.landmarks));
  Eigen::VectorXd z(p.unknowns());
  const lie::SE2 inv0 = poses[0].inverse();
  for (int i = 1; i < p.poses; ++i) {
    const lie::SE2 t = inv0 * poses[static_cast<std::size_t>(i)];
    z.segment<4>(4 * (i - 1)) << t.so2().cos_angle(), t.so2().sin_angle(), t.translation() / p.length_scale;
  }
  for (int l = 0; l < p.landmarks; ++l)
    z.segment<2>(4 * (p.poses - 1) + 2 * l) =
        inv0.act(landmarks[static_cast<std::size_t>(l)]) / p.length_scale;
  return z;
}

PlanarEstimate estimate_of(const PlanarProblem& p, const Eigen::VectorXd& z) {
  if (z.size() != p.unknowns())
    throw std::invalid_argument(
        fmt::format("sos::estimate_of: {} unknowns given, {} expected", z.size(), p.unknowns()));
  PlanarEstimate out;
  out.poses.push_back(lie::SE2::identity());
  for (int i = 1; i < p.poses; ++i) {
    const auto o = 4 * (i - 1);
    out.poses.emplace_back(p.length_scale * z(o + 2), p.length_scale * z(o + 3), std::atan2(z(o + 1), z(o)));
  }
  for (int l = 0; l < p.landmarks; ++l)
    out.landmarks.push_back(p.length_scale * z.segment<2>(4 * (p.poses - 1) + 2 * l));
  return out;
}

void project_rotations(const PlanarProblem& p, Eigen::VectorXd& z) {
  for (int i = 1; i < p.poses; ++i) {
    auto cs = z.segment<2>(4 * (i - 1));
    const double r = cs.norm();
    if (r > 0)
      cs /= r;
    else
      cs << 1.0, 0.0;
  }
}

Eigen::SparseMatrix<double> columns_of(const Eigen::SparseMatrix<double>& a, const std::vector<int>& cols) {
  Eigen::SparseMatrix<double> sel(a.cols(), static_cast<Eigen::Index>(cols.size()));
  std::vector<Triplet> t;
  for (std::size_t k = 0; k < cols.size(); ++k) t.emplace_back(cols[k], static_cast<int>(k), 1.0);
  sel.setFromTriplets(t.begin(), t.end());
  return a * sel;
}

void solve_translations(const PlanarProblem& p, Eigen::VectorXd& z) {
  // Columns of the translation and landmark unknowns, and the residual of the rotations alone.
  std::vector<int> cols;
  for (int v = 0; v < p.unknowns(); ++v)
    if (!p.is_rotation(v)) cols.push_back(v);
  Eigen::VectorXd zr = z;
  for (int v : cols) zr(v) = 0.0;
  const Eigen::VectorXd rhs = -(p.a * zr + p.r);
  const Eigen::SparseMatrix<double> at = columns_of(p.a, cols);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Eigen::SparseMatrix<double>(at.transpose() * at));
  if (ldlt.info() != Eigen::Success)
    throw std::runtime_error("sos::solve_translations: the translation system is singular");
  const Eigen::VectorXd zt = ldlt.solve(at.transpose() * rhs);
  for (std::size_t k = 0; k < cols.size(); ++k) z(cols[k]) = zt(static_cast<Eigen::Index>(k));
}

RefineResult refine(const PlanarProblem& p, Eigen::VectorXd& z, int max_iterations) {
  project_rotations(p, z);
  RefineResult out;
  out.initial_cost = polynomial_cost(p, z);
  const int nu = p.unknowns();
  // Parameters: θ_i in place of (c_i, s_i) (index of c_i), the other unknowns as they are; s_i's column
  // unused.
  auto jacobian_map = [&](const Eigen::VectorXd& zz) {
    std::vector<Triplet> t;
    for (int v = 0; v < nu; ++v) {
      if (p.is_rotation(v)) {
        if (v % 4 == 0) t.emplace_back(v, v, -zz(v + 1)), t.emplace_back(v + 1, v, zz(v));
      } else {
        t.emplace_back(v, v, 1.0);
      }
    }
    Eigen::SparseMatrix<double> d(nu, nu);
    d.setFromTriplets(t.begin(), t.end());
    return d;
  };
  double cost = out.initial_cost;
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::SparseMatrix<double> j = p.a * jacobian_map(z);
    const Eigen::VectorXd res = p.a * z + p.r;
    const Eigen::VectorXd g = j.transpose() * res;
    out.gradient_norm = 2.0 * g.cwiseAbs().maxCoeff();
    Eigen::SparseMatrix<double> h = j.transpose() * j;
    for (int v = 0; v < nu; ++v)
      if (p.is_rotation(v) && v % 4 == 1) h.coeffRef(v, v) += 1.0;  // the unused s column
    h.makeCompressed();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(h);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::VectorXd step = ldlt.solve(-g);
    auto moved = [&](double alpha) {
      Eigen::VectorXd trial = z;
      for (int v = 0; v < nu; ++v) {
        if (!p.is_rotation(v)) {
          trial(v) += alpha * step(v);
        } else if (v % 4 == 0) {
          const double th = std::atan2(z(v + 1), z(v)) + alpha * step(v);
          trial(v) = std::cos(th), trial(v + 1) = std::sin(th);
        }
      }
      return trial;
    };
    double alpha = 1.0, trial_cost = cost;
    Eigen::VectorXd trial;
    for (int k = 0; k < 12; ++k, alpha *= 0.5) {
      trial = moved(alpha);
      trial_cost = polynomial_cost(p, trial);
      if (trial_cost < cost) break;
    }
    if (!(trial_cost < cost)) break;
    const double gain = cost - trial_cost;
    z = trial, cost = trial_cost, out.iterations = it + 1;
    if (gain <= 1e-15 * std::max(1.0, cost)) break;
  }
  out.final_cost = cost;
  return out;
}

Segment extract_segment(const graph::PoseGraph2D& g, int first, int count,
                        const std::vector<lie::SE2>& truth_poses,
                        const std::vector<lie::Vec2>& truth_landmarks) {
  int n = static_cast<int>(g.poses.size());
  for (const auto& e : g.edges) n = std::max(n, std::max(e.i, e.j) + 1);
  if (count < 1)
    throw std::invalid_argument(fmt::format("sos::extract_segment: empty segment (count {})", count));
  if (first < 0 || first + count > n)
    throw std::invalid_argument(
        fmt::format("sos::extract_segment: poses {} … {} are outside the graph's 0 … {}", first,
                    first + count - 1, n - 1));
  if (!truth_poses.empty() && static_cast<int>(truth_poses.size()) < first + count)
    throw std::invalid_argument(
        "sos::extract_segment: the ground truth has fewer poses than the segment needs");
  Segment s;
  s.first = first;
  auto inside = [&](int i) { return i >= first && i < first + count; };
  std::vector<const graph::Edge2*> odometry(static_cast<std::size_t>(count), nullptr);
  for (const auto& e : g.edges)
    if (inside(e.i) && inside(e.j)) {
      graph::Edge2 c = e;
      c.i -= first, c.j -= first;
      s.graph.edges.push_back(c);
      if (c.j == c.i + 1 && !odometry[static_cast<std::size_t>(c.i)])
        odometry[static_cast<std::size_t>(c.i)] = &e;
    }
  s.graph.poses.push_back(lie::SE2::identity());
  for (int k = 0; k + 1 < count; ++k) {
    if (!odometry[static_cast<std::size_t>(k)])
      throw std::invalid_argument(fmt::format(
          "sos::extract_segment: no odometry edge ({}, {}) in the segment", first + k, first + k + 1));
    s.graph.poses.push_back(s.graph.poses.back() * odometry[static_cast<std::size_t>(k)]->measurement);
  }
  std::map<int, int> renumber;
  std::vector<int> original;
  for (const auto& m : g.landmark_measurements)
    if (inside(m.pose)) {
      auto [it, fresh] = renumber.emplace(m.landmark, static_cast<int>(original.size()));
      if (fresh) {
        original.push_back(m.landmark);
        s.graph.landmarks.push_back(s.graph.poses[static_cast<std::size_t>(m.pose - first)] * m.position);
      }
      graph::LandmarkMeasurement2 c = m;
      c.pose -= first, c.landmark = it->second;
      s.graph.landmark_measurements.push_back(c);
    }
  s.graph.source = fmt::format("{} [poses {} … {}]", g.source, first, first + count - 1);
  if (!truth_poses.empty()) {
    const lie::SE2 inv0 = truth_poses[static_cast<std::size_t>(first)].inverse();
    for (int k = 0; k < count; ++k)
      s.truth_poses.push_back(inv0 * truth_poses[static_cast<std::size_t>(first + k)]);
    if (!original.empty()) {
      if (truth_landmarks.empty())
        throw std::invalid_argument("sos::extract_segment: landmarks but no landmark ground truth");
      for (int l : original) {
        if (l >= static_cast<int>(truth_landmarks.size()))
          throw std::invalid_argument(
              fmt::format("sos::extract_segment: no ground truth for landmark {}", l));
        s.truth_landmarks.push_back(inv0.act(truth_landmarks[static_cast<std::size_t>(l)]));
      }
    }
  }
  return s;
}

}  // namespace keel::sos
