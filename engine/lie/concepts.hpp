// keel::lie — the LieGroup concept satisfied by SO2, SO3, SE2 and SE3.
#pragma once

#include <concepts>

#include "types.hpp"

namespace keel::lie {

/// A matrix Lie group with the interface used by the uncertainty engine.
///
/// Conventions (thesis ch. 5): left perturbation T = exp(xi^) T_bar (eq. 5.14);
/// adjoint(): exp(Ad_T xi) = T exp(xi) T^-1 (eqs. 5.9-5.10);
/// left_jacobian(xi): exp(xi + d) ~= exp(J_l(xi) d) exp(xi);
/// right_jacobian(xi): exp(xi + d) ~= exp(xi) exp(J_r(xi) d).
template <class G>
concept LieGroup = requires(const G& g, const typename G::Tangent& xi, const typename G::MatrixType& m,
                            const typename G::Point& p) {
  typename G::Tangent;
  typename G::Jacobian;
  typename G::MatrixType;
  typename G::Point;
  requires std::same_as<std::remove_cvref_t<decltype(G::DoF)>, int>;
  requires std::same_as<std::remove_cvref_t<decltype(G::Dim)>, int>;
  requires G::DoF >= 1;
  requires G::Tangent::RowsAtCompileTime == G::DoF&& G::Tangent::ColsAtCompileTime == 1;
  requires G::Jacobian::RowsAtCompileTime == G::DoF&& G::Jacobian::ColsAtCompileTime == G::DoF;
  requires G::MatrixType::RowsAtCompileTime == G::Dim&& G::MatrixType::ColsAtCompileTime == G::Dim;
  { G::identity() } -> std::same_as<G>;
  { G::exp(xi) } -> std::same_as<G>;
  { G::hat(xi) } -> std::same_as<typename G::MatrixType>;
  { G::vee(m) } -> std::same_as<typename G::Tangent>;
  { G::left_jacobian(xi) } -> std::same_as<typename G::Jacobian>;
  { G::right_jacobian(xi) } -> std::same_as<typename G::Jacobian>;
  { G::left_jacobian_inverse(xi) } -> std::same_as<typename G::Jacobian>;
  { G::right_jacobian_inverse(xi) } -> std::same_as<typename G::Jacobian>;
  { G::from_matrix(m) } -> std::same_as<G>;
  { g.log() } -> std::same_as<typename G::Tangent>;
  { g.inverse() } -> std::same_as<G>;
  { g* g } -> std::same_as<G>;
  { g.act(p) } -> std::same_as<typename G::Point>;
  { g* p } -> std::same_as<typename G::Point>;
  { g.adjoint() } -> std::same_as<typename G::Jacobian>;
  { g.matrix() } -> std::convertible_to<typename G::MatrixType>;
  { g.is_approx(g, 1e-9) } -> std::same_as<bool>;
};

}  // namespace keel::lie
