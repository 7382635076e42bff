#include "uncertain.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>

#include "gaussian.hpp"

namespace keel::lie {

namespace {

template <class M>
M symmetrized(const M& m) {
  return 0.5 * (m + m.transpose());
}

template <LieGroup G>
std::string group_name() {
  if constexpr (std::is_same_v<G, SO2>) return "SO2";
  if constexpr (std::is_same_v<G, SO3>) return "SO3";
  if constexpr (std::is_same_v<G, SE2>) return "SE2";
  if constexpr (std::is_same_v<G, SE3>) return "SE3";
  return "G";
}

template <LieGroup G>
void check_index(const JointPoses<G>& poses, std::size_t i, const char* fn) {
  if (i >= poses.size()) {
    throw std::invalid_argument(fmt::format("{}: pose index {} out of range (JointPoses<{}> has {} poses)",
                                            fn, i, group_name<G>(), poses.size()));
  }
}

// Appends a pose with mean `mean` and perturbation xi_new = sum_t A_t xi_{idx_t}
// (first-order linear map), carrying all cross-covariances along.
template <LieGroup G>
std::size_t append_linear(JointPoses<G>& poses, const G& mean,
                          const std::vector<std::pair<std::size_t, typename G::Jacobian>>& terms) {
  constexpr int D = G::DoF;
  const Eigen::Index n = static_cast<Eigen::Index>(poses.size());
  // Row block C_new,all = sum_t A_t Sigma_{idx_t, all}.
  MatX row = MatX::Zero(D, D * n);
  for (const auto& [idx, A] : terms) row += A * poses.cov.middleRows(D * static_cast<Eigen::Index>(idx), D);
  // C_new,new = sum_s C_new,idx_s A_s^T.
  typename G::Jacobian nn = G::Jacobian::Zero();
  for (const auto& [idx, A] : terms)
    nn += row.middleCols(D * static_cast<Eigen::Index>(idx), D) * A.transpose();
  MatX grown = MatX::Zero(D * (n + 1), D * (n + 1));
  grown.topLeftCorner(D * n, D * n) = poses.cov;
  grown.bottomLeftCorner(D, D * n) = row;
  grown.topRightCorner(D * n, D) = row.transpose();
  grown.bottomRightCorner<D, D>() = symmetrized(nn);
  poses.cov = std::move(grown);
  poses.means.push_back(mean);
  return poses.size() - 1;
}

}  // namespace

// ------------------------------------------------------------------------------------------
// UncertainPose / JointPoses members
// ------------------------------------------------------------------------------------------

template <LieGroup G>
void UncertainPose<G>::validate() const {
  validate_covariance(cov, fmt::format("UncertainPose<{}>", group_name<G>()));
}

template <LieGroup G>
void JointPoses<G>::check_dimensions() const {
  const Eigen::Index expected = static_cast<Eigen::Index>(G::DoF * means.size());
  if (cov.rows() != expected || cov.cols() != expected) {
    throw std::invalid_argument(
        fmt::format("JointPoses<{}>: joint covariance is {}x{} but {} poses of {} DoF need {}x{}",
                    group_name<G>(), cov.rows(), cov.cols(), means.size(), G::DoF, expected, expected));
  }
}

template <LieGroup G>
void JointPoses<G>::validate() const {
  check_dimensions();
  validate_covariance(cov, fmt::format("JointPoses<{}>", group_name<G>()));
}

template <LieGroup G>
UncertainPose<G> JointPoses<G>::marginal(std::size_t i) const {
  check_dimensions();
  check_index(*this, i, "JointPoses::marginal");
  const Eigen::Index o = G::DoF * static_cast<Eigen::Index>(i);
  return UncertainPose<G>(means[i], symmetrized(Jacobian(cov.block<G::DoF, G::DoF>(o, o))));
}

template <LieGroup G>
typename G::Jacobian JointPoses<G>::cross(std::size_t i, std::size_t j) const {
  check_dimensions();
  check_index(*this, i, "JointPoses::cross");
  check_index(*this, j, "JointPoses::cross");
  return cov.block<G::DoF, G::DoF>(G::DoF * static_cast<Eigen::Index>(i),
                                   G::DoF * static_cast<Eigen::Index>(j));
}

template <LieGroup G>
JointPoses<G> JointPoses<G>::independent(const std::vector<UncertainPose<G>>& poses) {
  JointPoses<G> out;
  const Eigen::Index n = static_cast<Eigen::Index>(poses.size());
  out.cov = MatX::Zero(G::DoF * n, G::DoF * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    poses[k].validate();
    out.means.push_back(poses[k].mean);
    out.cov.block<G::DoF, G::DoF>(G::DoF * k, G::DoF * k) = poses[k].cov;
  }
  return out;
}

// ------------------------------------------------------------------------------------------
// Composition (section 5.5)
// ------------------------------------------------------------------------------------------

template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const UncertainPose<G>& jk) {
  return compose(ij, jk, G::Jacobian::Zero());
}

// exp(xi_ik) T_ik = exp(xi_ij) T_ij exp(xi_jk) T_jk = exp(xi_ij) exp(Ad_{T_ij} xi_jk) T_ij T_jk
// (eq. 5.31); T_ik = T_ij T_jk (eq. 5.32); to first order xi_ik = xi_ij + Ad_{T_ij} xi_jk, so
// Sigma_ik = Sigma_ij + Ad Sigma_jk Ad^T + Sigma_{ij,jk} Ad^T + Ad Sigma_{ij,jk}^T (eq. 5.39).
template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const UncertainPose<G>& jk,
                         const typename G::Jacobian& cross_ij_jk) {
  const typename G::Jacobian Ad = ij.mean.adjoint();
  const typename G::Jacobian C = cross_ij_jk * Ad.transpose();
  const typename G::Jacobian cov = ij.cov + Ad * jk.cov * Ad.transpose() + C + C.transpose();
  return UncertainPose<G>(ij.mean * jk.mean, symmetrized(cov));
}

// K T = K exp(xi) T_bar = exp(Ad_K xi) K T_bar (eq. 5.10): the perturbation is mapped
// linearly and exactly, Sigma' = Ad_K Sigma Ad_K^T.
template <LieGroup G>
UncertainPose<G> compose(const G& known_ij, const UncertainPose<G>& jk) {
  const typename G::Jacobian Ad = known_ij.adjoint();
  return UncertainPose<G>(known_ij * jk.mean,
                          symmetrized(typename G::Jacobian(Ad * jk.cov * Ad.transpose())));
}

// T K = exp(xi) (T_bar K): the left perturbation is untouched, Sigma' = Sigma (exact).
template <LieGroup G>
UncertainPose<G> compose(const UncertainPose<G>& ij, const G& known_jk) {
  return UncertainPose<G>(ij.mean * known_jk, ij.cov);
}

template <LieGroup G>
UncertainPose<G> compose(const JointPoses<G>& poses, std::size_t i, std::size_t j, bool use_cross) {
  poses.check_dimensions();
  check_index(poses, i, "compose(JointPoses)");
  check_index(poses, j, "compose(JointPoses)");
  const UncertainPose<G> a = poses.marginal(i);
  const UncertainPose<G> b = poses.marginal(j);
  return use_cross ? compose(a, b, poses.cross(i, j)) : compose(a, b);
}

// ------------------------------------------------------------------------------------------
// Inverse (section 5.6): T^-1 = T_bar^-1 exp(-xi) = exp(-Ad_{T_bar^-1} xi) T_bar^-1 (eq. 5.43),
// T_ji = T_ij^-1 (eq. 5.44), Sigma_ji = Ad_{T_ij^-1} Sigma_ij Ad_{T_ij^-1}^T (eq. 5.45).
// ------------------------------------------------------------------------------------------

template <LieGroup G>
UncertainPose<G> inverse(const UncertainPose<G>& ij) {
  const G inv = ij.mean.inverse();
  const typename G::Jacobian A = inv.adjoint();
  return UncertainPose<G>(inv, symmetrized(typename G::Jacobian(A * ij.cov * A.transpose())));
}

// ------------------------------------------------------------------------------------------
// Relative pose (section 5.7).
//
// Derivation of the signs of eq. 5.51 (the thesis typesetting is garbled):
//   T_jk = T_ij^-1 T_ik = T_ij_bar^-1 exp(-xi_ij) exp(xi_ik) T_ik_bar                 (5.46-5.47)
//        = exp(-A xi_ij) T_ij_bar^-1 exp(xi_ik) T_ik_bar,           A = Ad_{T_ij_bar^-1}
//        = exp(xi'_ij) exp(xi'_ik) T_ij_bar^-1 T_ik_bar,   xi'_ij = -A xi_ij, xi'_ik = A xi_ik,
// so T_jk_bar = T_ij_bar^-1 T_ik_bar (5.48) and, to first order in BCH (5.49-5.50),
//   xi_jk ~= xi'_ij + xi'_ik = A (xi_ik - xi_ij).
// Taking E[xi_jk xi_jk^T] with Sigma_{ij,ik} = E[xi_ij xi_ik^T]:
//   E[xi'_ij xi'_ij^T] = A Sigma_ij A^T,       E[xi'_ik xi'_ik^T] = A Sigma_ik A^T,
//   E[xi'_ij xi'_ik^T] = -A Sigma_{ij,ik} A^T, E[xi'_ik xi'_ij^T] = -A Sigma_{ij,ik}^T A^T,
//   Sigma_jk = A Sigma_ij A^T + A Sigma_ik A^T - A Sigma_{ij,ik} A^T - A Sigma_{ij,ik}^T A^T.   (5.51)
// Both cross terms enter with a MINUS sign: positive correlation reduces the relative
// uncertainty, so ignoring it over-estimates Sigma_jk (Fig. 5.5).
// ------------------------------------------------------------------------------------------

template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const UncertainPose<G>& ik) {
  return relative(ij, ik, G::Jacobian::Zero());
}

template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const UncertainPose<G>& ik,
                          const typename G::Jacobian& cross_ij_ik) {
  const G ij_inv = ij.mean.inverse();
  const typename G::Jacobian A = ij_inv.adjoint();
  const typename G::Jacobian inner = ij.cov + ik.cov - cross_ij_ik - cross_ij_ik.transpose();
  return UncertainPose<G>(ij_inv * ik.mean, symmetrized(typename G::Jacobian(A * inner * A.transpose())));
}

// K^-1 exp(xi_ik) T_ik_bar = exp(Ad_{K^-1} xi_ik) K^-1 T_ik_bar (exact).
template <LieGroup G>
UncertainPose<G> relative(const G& known_ij, const UncertainPose<G>& ik) {
  return compose(known_ij.inverse(), ik);
}

// T_ij_bar^-1 exp(-xi_ij) K = exp(-Ad_{T_ij_bar^-1} xi_ij) T_ij_bar^-1 K (exact).
template <LieGroup G>
UncertainPose<G> relative(const UncertainPose<G>& ij, const G& known_ik) {
  return compose(inverse(ij), known_ik);
}

template <LieGroup G>
UncertainPose<G> relative(const JointPoses<G>& poses, std::size_t i, std::size_t k, bool use_cross) {
  poses.check_dimensions();
  check_index(poses, i, "relative(JointPoses)");
  check_index(poses, k, "relative(JointPoses)");
  const UncertainPose<G> a = poses.marginal(i);
  const UncertainPose<G> b = poses.marginal(k);
  return use_cross ? relative(a, b, poses.cross(i, k)) : relative(a, b);
}

// ------------------------------------------------------------------------------------------
// Growing joint distributions and chains
// ------------------------------------------------------------------------------------------

template <LieGroup G>
std::size_t append_composition(JointPoses<G>& poses, std::size_t i, std::size_t j) {
  poses.check_dimensions();
  check_index(poses, i, "append_composition");
  check_index(poses, j, "append_composition");
  using J = typename G::Jacobian;
  const G mean = poses.means[i] * poses.means[j];
  return append_linear(poses, mean, {{i, J::Identity()}, {j, poses.means[i].adjoint()}});
}

template <LieGroup G>
std::size_t append_inverse(JointPoses<G>& poses, std::size_t i) {
  poses.check_dimensions();
  check_index(poses, i, "append_inverse");
  const G inv = poses.means[i].inverse();
  return append_linear(poses, inv, {{i, typename G::Jacobian(-inv.adjoint())}});
}

template <LieGroup G>
std::size_t append_relative(JointPoses<G>& poses, std::size_t i, std::size_t k) {
  poses.check_dimensions();
  check_index(poses, i, "append_relative");
  check_index(poses, k, "append_relative");
  const G inv = poses.means[i].inverse();
  const typename G::Jacobian A = inv.adjoint();
  return append_linear(poses, G(inv * poses.means[k]), {{i, typename G::Jacobian(-A)}, {k, A}});
}

// T_1 ... T_n = exp(xi_1) T_1 exp(xi_2) T_2 ... = exp(xi_1) exp(Ad_{P_1} xi_2) exp(Ad_{P_2} xi_3) ... P_n
// with P_k = T_1 ... T_k (eq. 5.10 applied repeatedly); to first order (eq. 5.39 repeated,
// cross-covariances carried along) xi = sum_k Ad_{P_{k-1}} xi_k.
template <LieGroup G>
MatX chain_jacobian(const JointPoses<G>& poses) {
  poses.check_dimensions();
  constexpr int D = G::DoF;
  const Eigen::Index n = static_cast<Eigen::Index>(poses.size());
  MatX J(D, D * n);
  G prefix = G::identity();
  for (Eigen::Index k = 0; k < n; ++k) {
    J.middleCols<D>(D * k) = prefix.adjoint();
    prefix = prefix * poses.means[k];
  }
  return J;
}

template <LieGroup G>
UncertainPose<G> compose_chain(const JointPoses<G>& poses, bool use_cross) {
  poses.check_dimensions();
  if (poses.size() == 0) throw std::invalid_argument("compose_chain: empty JointPoses");
  constexpr int D = G::DoF;
  const MatX J = chain_jacobian(poses);
  G mean = G::identity();
  for (const G& m : poses.means) mean = mean * m;
  typename G::Jacobian cov;
  if (use_cross) {
    cov = J * poses.cov * J.transpose();
  } else {
    cov.setZero();
    for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(poses.size()); ++k) {
      const auto Jk = J.middleCols<D>(D * k);
      cov += Jk * poses.cov.template block<D, D>(D * k, D * k) * Jk.transpose();
    }
  }
  return UncertainPose<G>(mean, symmetrized(cov));
}

template <LieGroup G>
UncertainPose<G> compose_chain(const std::vector<UncertainPose<G>>& poses) {
  if (poses.empty()) throw std::invalid_argument("compose_chain: empty pose list");
  UncertainPose<G> acc = poses.front();
  for (std::size_t k = 1; k < poses.size(); ++k) acc = compose(acc, poses[k]);
  return acc;
}

// ------------------------------------------------------------------------------------------
// Barfoot & Furgale (2014) fourth-order compounding (independent SE(3) poses).
//
// With xi'_2 = Ad(T_1) xi_2 and the BCH expansion (eq. 5.13 / 5.34)
//   xi = xi_1 + xi'_2 + 1/2 xi_1^c xi'_2 + 1/12 xi_1^c xi_1^c xi'_2 + 1/12 xi'_2^c xi'_2^c xi_1 + ...
// (^c = curly hat of eq. 5.12), keeping all terms of E[xi xi^T] up to fourth order in the
// perturbations (odd moments vanish; independence kills the cross terms of eq. 5.35/5.37):
//   Sigma_4th = Sigma_1 + Sigma_2' + 1/4 B + 1/12 (A_1 Sigma_2' + Sigma_2' A_1^T + A_2' Sigma_1 + Sigma_1
//   A_2'^T)
// with A_1 = E[xi_1^c xi_1^c] = <<Sigma_1>>, A_2' = <<Sigma_2'>>, B = E[xi_1^c Sigma_2' xi_1^c^T].
// ------------------------------------------------------------------------------------------

Mat3 double_bracket(const Mat3& A) { return -A.trace() * Mat3::Identity() + A; }

Mat3 double_bracket(const Mat3& A, const Mat3& B) {
  return double_bracket(A) * double_bracket(B) + double_bracket(Mat3(B * A));
}

Mat6 double_bracket(const Mat6& S) {
  const Mat3 Srp = S.topRightCorner<3, 3>();
  const Mat3 Spp = S.bottomRightCorner<3, 3>();
  Mat6 out = Mat6::Zero();
  out.topLeftCorner<3, 3>() = double_bracket(Spp);
  out.bottomRightCorner<3, 3>() = double_bracket(Spp);
  out.topRightCorner<3, 3>() = double_bracket(Mat3(Srp + Srp.transpose()));
  return out;
}

Mat6 fourth_order_b_matrix(const Mat6& S1, const Mat6& S2) {
  const Mat3 S1rr = S1.topLeftCorner<3, 3>();
  const Mat3 S1rp = S1.topRightCorner<3, 3>();
  const Mat3 S1pp = S1.bottomRightCorner<3, 3>();
  const Mat3 S2rr = S2.topLeftCorner<3, 3>();
  const Mat3 S2rp = S2.topRightCorner<3, 3>();
  const Mat3 S2pp = S2.bottomRightCorner<3, 3>();
  const Mat3 Brr = double_bracket(S1pp, S2rr) + double_bracket(Mat3(S1rp.transpose()), S2rp) +
                   double_bracket(S1rp, Mat3(S2rp.transpose())) + double_bracket(S1rr, S2pp);
  const Mat3 Brp =
      double_bracket(S1pp, Mat3(S2rp.transpose())) + double_bracket(Mat3(S1rp.transpose()), S2pp);
  const Mat3 Bpp = double_bracket(S1pp, S2pp);
  Mat6 B;
  B << Brr, Brp, Brp.transpose(), Bpp;
  return B;
}

UncertainPose<SE3> compose_fourth_order(const UncertainPose<SE3>& ij, const UncertainPose<SE3>& jk) {
  const Mat6 Ad = ij.mean.adjoint();
  const Mat6& S1 = ij.cov;
  const Mat6 S2 = symmetrized(Mat6(Ad * jk.cov * Ad.transpose()));
  const Mat6 A1 = double_bracket(S1);
  const Mat6 A2 = double_bracket(S2);
  const Mat6 B = fourth_order_b_matrix(S1, S2);
  const Mat6 cov =
      S1 + S2 + 0.25 * B + (A1 * S2 + S2 * A1.transpose() + A2 * S1 + S1 * A2.transpose()) / 12.0;
  return UncertainPose<SE3>(ij.mean * jk.mean, symmetrized(cov));
}

UncertainPose<SE3> compose_chain_fourth_order(const std::vector<UncertainPose<SE3>>& poses) {
  if (poses.empty()) throw std::invalid_argument("compose_chain_fourth_order: empty pose list");
  UncertainPose<SE3> acc = poses.front();
  for (std::size_t k = 1; k < poses.size(); ++k) acc = compose_fourth_order(acc, poses[k]);
  return acc;
}

// ------------------------------------------------------------------------------------------
// Explicit instantiations
// ------------------------------------------------------------------------------------------

#define KEEL_LIE_INSTANTIATE_UNCERTAIN(G)                                                      \
  template struct UncertainPose<G>;                                                            \
  template struct JointPoses<G>;                                                               \
  template UncertainPose<G> compose<G>(const UncertainPose<G>&, const UncertainPose<G>&);      \
  template UncertainPose<G> compose<G>(const UncertainPose<G>&, const UncertainPose<G>&,       \
                                       const typename G::Jacobian&);                           \
  template UncertainPose<G> compose<G>(const G&, const UncertainPose<G>&);                     \
  template UncertainPose<G> compose<G>(const UncertainPose<G>&, const G&);                     \
  template UncertainPose<G> compose<G>(const JointPoses<G>&, std::size_t, std::size_t, bool);  \
  template UncertainPose<G> inverse<G>(const UncertainPose<G>&);                               \
  template UncertainPose<G> relative<G>(const UncertainPose<G>&, const UncertainPose<G>&);     \
  template UncertainPose<G> relative<G>(const UncertainPose<G>&, const UncertainPose<G>&,      \
                                        const typename G::Jacobian&);                          \
  template UncertainPose<G> relative<G>(const G&, const UncertainPose<G>&);                    \
  template UncertainPose<G> relative<G>(const UncertainPose<G>&, const G&);                    \
  template UncertainPose<G> relative<G>(const JointPoses<G>&, std::size_t, std::size_t, bool); \
  template std::size_t append_composition<G>(JointPoses<G>&, std::size_t, std::size_t);        \
  template std::size_t append_inverse<G>(JointPoses<G>&, std::size_t);                         \
  template std::size_t append_relative<G>(JointPoses<G>&, std::size_t, std::size_t);           \
  template MatX chain_jacobian<G>(const JointPoses<G>&);                                       \
  template UncertainPose<G> compose_chain<G>(const JointPoses<G>&, bool);                      \
  template UncertainPose<G> compose_chain<G>(const std::vector<UncertainPose<G>>&);

KEEL_LIE_INSTANTIATE_UNCERTAIN(SO2)
KEEL_LIE_INSTANTIATE_UNCERTAIN(SO3)
KEEL_LIE_INSTANTIATE_UNCERTAIN(SE2)
KEEL_LIE_INSTANTIATE_UNCERTAIN(SE3)

#undef KEEL_LIE_INSTANTIATE_UNCERTAIN

}  // namespace keel::lie
