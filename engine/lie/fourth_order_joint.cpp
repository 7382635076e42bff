// Fourth-order composition of correlated SE(3) poses (thesis §5.5.1, eqs. 5.34-5.39 and the
// footnote on Isserlis' theorem; Barfoot & Furgale 2014, Sec. III; Isserlis 1918).
// See fourth_order_joint.hpp for the derivation summary and conventions.
#include "fourth_order_joint.hpp"

#include <array>
#include <stdexcept>
#include <vector>

#include "core/names.hpp"

namespace keel::lie {

namespace {

template <class M>
M symmetrized(const M& m) {
  return 0.5 * (m + m.transpose());
}

// Structure constants of se(3) in the curly-hat basis: [v, w] = v^c w, so
// [v, w]_i = sum_ab v_a eps(i, a, b) w_b with eps(i, a, b) = (G_a)_{ib}, G_a = curly_hat(e_a).
// E[i] is the 6x6 matrix (a, b) -> eps(i, a, b), so [v, w]_i = v^T E[i] w.
struct StructureConstants {
  std::array<Mat6, 6> E;
  StructureConstants() {
    for (int a = 0; a < 6; ++a) {
      const Mat6 G = SE3::curly_hat(Vec6::Unit(a));
      for (int i = 0; i < 6; ++i)
        for (int b = 0; b < 6; ++b) E[static_cast<std::size_t>(i)](a, b) = G(i, b);
    }
  }
  double operator()(int i, int a, int b) const { return E[static_cast<std::size_t>(i)](a, b); }
};

const StructureConstants& eps() {
  static const StructureConstants k;
  return k;
}

// Isserlis (1918): E[z_a z_b z_c z_d] for z ~ N(0, S).
template <class M>
double isserlis4(const M& S, int a, int b, int c, int d) {
  return S(a, b) * S(c, d) + S(a, c) * S(b, d) + S(a, d) * S(b, c);
}

// The BCH polynomial of eq. 5.34 in z = [x; y] (12-vector), truncated at degree 3:
//   xi_i = sum_a P(i, a) z_a + sum_ab q[i](a, b) z_a z_b + sum_abc t[i][(a*12+b)*12+c] z_a z_b z_c.
struct BchPolynomial {
  static constexpr int n = 12;
  Eigen::Matrix<double, 6, 12> P;
  std::array<Mat12, 6> q;
  std::array<std::vector<double>, 6> t;

  BchPolynomial() {
    const auto& e = eps();
    P << Mat6::Identity(), Mat6::Identity();
    for (auto& m : q) m.setZero();
    for (auto& v : t) v.assign(static_cast<std::size_t>(n * n * n), 0.0);
    for (int i = 0; i < 6; ++i) {
      auto& qi = q[static_cast<std::size_t>(i)];
      auto& ti = t[static_cast<std::size_t>(i)];
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b) qi(a, 6 + b) = 0.5 * e(i, a, b);  // 1/2 x^c y
      // 1/12 x^c (x^c y):  (x^c x^c y)_i = sum_{a,b,c,d} eps(i,a,b) x_a eps(b,c,d) x_c y_d
      // 1/12 y^c (y^c x):  same with x <-> y.
      for (int a = 0; a < 6; ++a)
        for (int c = 0; c < 6; ++c)
          for (int d = 0; d < 6; ++d) {
            double coef = 0.0;
            for (int b = 0; b < 6; ++b) coef += e(i, a, b) * e(b, c, d);
            coef /= 12.0;
            ti[static_cast<std::size_t>((a * n + c) * n + (6 + d))] += coef;
            ti[static_cast<std::size_t>(((6 + a) * n + (6 + c)) * n + d)] += coef;
          }
    }
  }
};

const BchPolynomial& bch_polynomial() {
  static const BchPolynomial p;
  return p;
}

// E[C_i w_j] for the cubic part C of the BCH polynomial and a Gaussian w jointly distributed
// with z: Szw = E[z w^T] (12 x 6).  Isserlis: E[z_a z_b z_c w] = S_ab S_cw + S_ac S_bw + S_bc S_aw.
Mat6 cubic_cross_moment(const Mat12& S, const Eigen::Matrix<double, 12, 6>& Szw) {
  const auto& poly = bch_polynomial();
  constexpr int n = BchPolynomial::n;
  Mat6 out = Mat6::Zero();
  for (int i = 0; i < 6; ++i) {
    const auto& ti = poly.t[static_cast<std::size_t>(i)];
    // v = sum_abc t_abc (S_ab e_c + S_ac e_b + S_bc e_a)  (a 12-vector), then out.row(i) = v^T Szw.
    Eigen::Matrix<double, 12, 1> v = Eigen::Matrix<double, 12, 1>::Zero();
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        for (int c = 0; c < n; ++c) {
          const double tv = ti[static_cast<std::size_t>((a * n + b) * n + c)];
          if (tv == 0.0) continue;
          v(c) += tv * S(a, b);
          v(b) += tv * S(a, c);
          v(a) += tv * S(b, c);
        }
    out.row(i) = v.transpose() * Szw;
  }
  return out;
}

Mat12 joint_block(const Mat6& S1, const Mat6& S2, const Mat6& C) {
  Mat12 S;
  S << S1, C, C.transpose(), S2;
  return S;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// Single composition (brute-force Isserlis sums)
// ------------------------------------------------------------------------------------------

Mat6 bch_second_moment_fourth_order(const Mat12& S, Vec6* mean) {
  const auto& poly = bch_polynomial();
  constexpr int n = BchPolynomial::n;
  // Second order: E[L L^T] = P S P^T (eq. 5.38 / 5.39).
  Mat6 M = poly.P * S * poly.P.transpose();
  // Fourth order, square of the second-order term: E[Q_i Q_j] = sum q_i,ab q_j,cd E[z_a z_b z_c z_d].
  Mat6 QQ = Mat6::Zero();
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) {
      const Mat12& qi = poly.q[static_cast<std::size_t>(i)];
      const Mat12& qj = poly.q[static_cast<std::size_t>(j)];
      double s = 0.0;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          if (qi(a, b) == 0.0) continue;
          for (int c = 0; c < n; ++c)
            for (int d = 0; d < n; ++d) {
              if (qj(c, d) == 0.0) continue;
              s += qi(a, b) * qj(c, d) * isserlis4(S, a, b, c, d);
            }
        }
      QQ(i, j) = QQ(j, i) = s;
    }
  // Fourth order, first-order term times the third-order (1/12) terms:
  // E[L_i C_j] = sum_a P(i,a) sum_bcd t_j,bcd E[z_a z_b z_c z_d].
  Mat6 LC = Mat6::Zero();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const auto& tj = poly.t[static_cast<std::size_t>(j)];
      double s = 0.0;
      for (int a = 0; a < n; ++a) {
        if (poly.P(i, a) == 0.0) continue;
        for (int b = 0; b < n; ++b)
          for (int c = 0; c < n; ++c)
            for (int d = 0; d < n; ++d) {
              const double tv = tj[static_cast<std::size_t>((b * n + c) * n + d)];
              if (tv == 0.0) continue;
              s += poly.P(i, a) * tv * isserlis4(S, a, b, c, d);
            }
      }
      LC(i, j) = s;
    }
  M += QQ + LC + LC.transpose();
  if (mean) {
    // E[Q_i] = sum_ab q_i,ab S_ab (E[L] = E[C] = 0).
    for (int i = 0; i < 6; ++i) (*mean)(i) = poly.q[static_cast<std::size_t>(i)].cwiseProduct(S).sum();
  }
  return symmetrized(M);
}

UncertainPose<SE3> compose_fourth_order_joint(const UncertainPose<SE3>& ij, const UncertainPose<SE3>& jk,
                                              const Mat6& cross_ij_jk, Vec6* perturbation_mean) {
  const Mat6 Ad = ij.mean.adjoint();
  const Mat6 S2 = symmetrized(Mat6(Ad * jk.cov * Ad.transpose()));
  const Mat12 S = joint_block(ij.cov, S2, Mat6(cross_ij_jk * Ad.transpose()));
  return UncertainPose<SE3>(ij.mean * jk.mean, bch_second_moment_fourth_order(S, perturbation_mean));
}

UncertainPose<SE3> compose_fourth_order_joint(const JointPoses<SE3>& poses, std::size_t i, std::size_t j,
                                              Vec6* perturbation_mean) {
  poses.check_dimensions();
  if (i >= poses.size() || j >= poses.size())
    throw std::invalid_argument("compose_fourth_order_joint: pose index out of range");
  return compose_fourth_order_joint(poses.marginal(i), poses.marginal(j), poses.cross(i, j),
                                    perturbation_mean);
}

// ------------------------------------------------------------------------------------------
// Sequential chain
// ------------------------------------------------------------------------------------------

namespace {
constexpr core::NameTable<ChainCrossOrder, 2> kChainCrossOrderNames{"lie::ChainCrossOrder",
                                                                    {{
                                                                        {ChainCrossOrder::first, "first"},
                                                                        {ChainCrossOrder::fourth, "fourth"},
                                                                    }}};
}  // namespace

std::string_view to_string(ChainCrossOrder v) { return kChainCrossOrderNames.name(v); }
ChainCrossOrder chain_cross_order_from_string(std::string_view s) { return kChainCrossOrderNames.parse(s); }

Mat6 chain_second_moment_fourth_order_sequential(const JointPoses<SE3>& poses, ChainCrossOrder cross) {
  poses.check_dimensions();
  const std::size_t N = poses.size();
  if (N == 0) throw std::invalid_argument("chain_second_moment_fourth_order_sequential: empty pose list");
  SE3 mean = poses.means.front();
  Mat6 cov = poses.cov.topLeftCorner<6, 6>();
  // K = E[xi_{1:k} xi_all^T] (6 x 6N); only the columns of the steps not yet composed are used.
  MatX K = poses.cov.topRows(6);
  for (std::size_t k = 1; k < N; ++k) {
    const Eigen::Index ck = static_cast<Eigen::Index>(6 * k);
    const Mat6 Ad = mean.adjoint();
    const Mat6 Sk = poses.cov.block<6, 6>(ck, ck);
    const Mat6 Kk = K.middleCols<6>(ck);
    const Mat12 S = joint_block(cov, symmetrized(Mat6(Ad * Sk * Ad.transpose())), Mat6(Kk * Ad.transpose()));
    const Mat6 new_cov = bch_second_moment_fourth_order(S);
    // Cross-covariances with the remaining steps m > k.
    for (std::size_t m = k + 1; m < N; ++m) {
      const Eigen::Index cm = static_cast<Eigen::Index>(6 * m);
      const Mat6 Ckm = poses.cov.block<6, 6>(ck, cm);  // E[xi_k xi_m^T]
      Mat6 Knew = K.middleCols<6>(cm) + Ad * Ckm;
      if (cross == ChainCrossOrder::fourth) {
        Eigen::Matrix<double, 12, 6> Szw;
        Szw << K.middleCols<6>(cm), Ad * Ckm;
        Knew += cubic_cross_moment(S, Szw);
      }
      K.middleCols<6>(cm) = Knew;
    }
    cov = new_cov;
    mean = mean * poses.means[k];
  }
  return symmetrized(cov);
}

UncertainPose<SE3> compose_chain_fourth_order_joint(const JointPoses<SE3>& poses, ChainCrossOrder cross) {
  const Mat6 cov = chain_second_moment_fourth_order_sequential(poses, cross);
  SE3 mean = poses.means.front();
  for (std::size_t k = 1; k < poses.size(); ++k) mean = mean * poses.means[k];
  return UncertainPose<SE3>(mean, cov);
}

// ------------------------------------------------------------------------------------------
// Exact-to-fourth-order chain (cubic polynomial in the stacked perturbations)
// ------------------------------------------------------------------------------------------

Mat6 chain_second_moment_fourth_order(const JointPoses<SE3>& poses, Vec6* perturbation_mean) {
  poses.check_dimensions();
  const std::size_t N = poses.size();
  if (N == 0) throw std::invalid_argument("chain_second_moment_fourth_order: empty pose list");
  const Eigen::Index n = static_cast<Eigen::Index>(6 * N);
  const std::size_t n3 = static_cast<std::size_t>(n * n * n);
  const auto& E = eps().E;
  const MatX& S = poses.cov;

  // xi_{1:k}(u) = A u + sum_i e_i u^T Mq[i] u + sum_i e_i T[i](u, u, u),  u = [xi_1; ...; xi_N].
  MatX A = MatX::Zero(6, n);
  A.leftCols<6>().setIdentity();
  std::array<MatX, 6> Mq;
  for (auto& m : Mq) m = MatX::Zero(n, n);
  std::array<std::vector<double>, 6> T;
  for (auto& t : T) t.assign(n3, 0.0);

  SE3 mean = poses.means.front();
  for (std::size_t k = 1; k < N; ++k) {
    const Eigen::Index ck = static_cast<Eigen::Index>(6 * k);
    MatX Y = MatX::Zero(6, n);  // y = Y u = Ad(T_bar_{1:k}) xi_{k+1}
    Y.middleCols<6>(ck) = mean.adjoint();
    // Quadratic forms of the brackets [A u, Y u]_b = u^T P[b] u and [Y u, A u]_b = u^T R[b] u.
    std::array<MatX, 6> P, R;
    for (int b = 0; b < 6; ++b) {
      P[static_cast<std::size_t>(b)] = A.transpose() * E[static_cast<std::size_t>(b)] * Y;
      R[static_cast<std::size_t>(b)] = Y.transpose() * E[static_cast<std::size_t>(b)] * A;
    }
    std::array<std::vector<double>, 6> Tn = T;
    for (int i = 0; i < 6; ++i) {
      const Mat6& Ei = E[static_cast<std::size_t>(i)];
      const MatX W = Ei * Y;               // (a, r): sum_b eps(i,a,b) Y(b, r)
      const MatX Za = A.transpose() * Ei;  // (p, b): sum_a A(a,p) eps(i,a,b)
      const MatX Zy = Y.transpose() * Ei;  // (p, b): sum_a Y(a,p) eps(i,a,b)
      auto& ti = Tn[static_cast<std::size_t>(i)];
      for (Eigen::Index p = 0; p < n; ++p)
        for (Eigen::Index q = 0; q < n; ++q) {
          double* row = ti.data() + static_cast<std::size_t>((p * n + q) * n);
          // 1/2 [Q(u), Y u]_i = 1/2 sum_a Q_a(u) (W u)_a
          for (int a = 0; a < 6; ++a) {
            const double mq = 0.5 * Mq[static_cast<std::size_t>(a)](p, q);
            if (mq == 0.0) continue;
            for (Eigen::Index r = ck; r < ck + 6; ++r) row[r] += mq * W(a, r);
          }
          // 1/12 [A u, [A u, Y u]]_i + 1/12 [Y u, [Y u, A u]]_i
          for (int b = 0; b < 6; ++b) {
            const double za = Za(p, b) / 12.0, zy = Zy(p, b) / 12.0;
            if (za == 0.0 && zy == 0.0) continue;
            const MatX& Pb = P[static_cast<std::size_t>(b)];
            const MatX& Rb = R[static_cast<std::size_t>(b)];
            for (Eigen::Index r = 0; r < n; ++r) row[r] += za * Pb(q, r) + zy * Rb(q, r);
          }
        }
    }
    T = std::move(Tn);
    for (int i = 0; i < 6; ++i) Mq[static_cast<std::size_t>(i)] += 0.5 * P[static_cast<std::size_t>(i)];
    A += Y;
    mean = mean * poses.means[k];
  }

  // Moments (Isserlis).  Symmetric parts of the quadratic forms: Ms_i = (Mq_i + Mq_i^T) / 2.
  std::array<MatX, 6> SMS;  // S Ms_i
  Vec6 m;
  for (int i = 0; i < 6; ++i) {
    const MatX Ms = 0.5 * (Mq[static_cast<std::size_t>(i)] + Mq[static_cast<std::size_t>(i)].transpose());
    m(i) = Ms.cwiseProduct(S).sum();  // E[Q_i] = tr(Ms_i S)
    SMS[static_cast<std::size_t>(i)] = S * Ms;
  }
  // E[Q_i Q_j] = tr(Ms_i S) tr(Ms_j S) + 2 tr(S Ms_i S Ms_j).
  Mat6 QQ;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j)
      QQ(i, j) = QQ(j, i) =
          m(i) * m(j) + 2.0 * SMS[static_cast<std::size_t>(i)]
                                  .cwiseProduct(SMS[static_cast<std::size_t>(j)].transpose())
                                  .sum();
  // E[L_i C_j] = sum_pqr T_j,pqr (v_p S_qr + v_q S_pr + v_r S_pq), v = S A_i^T:
  // = (A S w_j)_i with w_j,p = sum_qr T_j,pqr S_qr + sum_qr T_j,qpr S_qr + sum_qr T_j,qrp S_qr.
  MatX Wc = MatX::Zero(n, 6);
  for (int j = 0; j < 6; ++j) {
    const auto& tj = T[static_cast<std::size_t>(j)];
    for (Eigen::Index p = 0; p < n; ++p)
      for (Eigen::Index q = 0; q < n; ++q) {
        const double* row = tj.data() + static_cast<std::size_t>((p * n + q) * n);
        double s_pq_r = 0.0;  // sum_r T_pqr S_qr  (for w_p)
        double s_pr = 0.0;    // contributions to w_q: sum_r T_pqr S_pr
        for (Eigen::Index r = 0; r < n; ++r) {
          const double tv = row[r];
          if (tv == 0.0) continue;
          s_pq_r += tv * S(q, r);
          s_pr += tv * S(p, r);
          Wc(r, j) += tv * S(p, q);  // w_r += T_pqr S_pq
        }
        Wc(p, j) += s_pq_r;
        Wc(q, j) += s_pr;
      }
  }
  const Mat6 LC = A * S * Wc;
  const Mat6 cov = A * S * A.transpose() + QQ + LC + LC.transpose();
  if (perturbation_mean) *perturbation_mean = m;
  return symmetrized(cov);
}

UncertainPose<SE3> compose_chain_fourth_order_joint_exact(const JointPoses<SE3>& poses,
                                                          Vec6* perturbation_mean) {
  const Mat6 cov = chain_second_moment_fourth_order(poses, perturbation_mean);
  SE3 mean = poses.means.front();
  for (std::size_t k = 1; k < poses.size(); ++k) mean = mean * poses.means[k];
  return UncertainPose<SE3>(mean, cov);
}

}  // namespace keel::lie
