// The shared test kit of every area's unit tests (docs/DESIGN.md "Naming and errors"): numerical Jacobians by
// central differences, random matrices, SPD matrices, tangents and poses drawn from keel::core::Rng
// (identical on every standard library, unlike std::normal_distribution), and a check that a call throws a
// given message. Unit tests include it as "kit/test_kit.hpp"; it imports nothing (DESIGN rule 4).
#pragma once

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "core/random.hpp"
#include "lie/se2.hpp"
#include "lie/se3.hpp"

namespace keel::testkit {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

// Central-difference Jacobian of f: R^n -> R^m at x, f(x) returning any Eigen vector expression.
template <class F>
MatX numerical_jacobian(const F& f, const VecX& x, double h = 1e-6) {
  VecX xp = x, xm = x;
  const VecX f0 = f(x);
  MatX J(f0.size(), x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    xp(k) = x(k) + h;
    xm(k) = x(k) - h;
    J.col(k) = (VecX(f(xp)) - VecX(f(xm))) / (2.0 * h);
    xp(k) = xm(k) = x(k);
  }
  return J;
}

// Central-difference Jacobian of a function of a group perturbation δ ∈ R^DoF at δ = 0: f(δ) is called with
// ±h e_k as a G::Tangent (the caller decides how δ enters, e.g. exp(δ^) T for the left perturbation of
// eq. 5.14).
template <class G, class F>
MatX numerical_jacobian_tangent(const F& f, double h = 1e-6) {
  const VecX f0 = f(typename G::Tangent(G::Tangent::Zero()));
  MatX J(f0.size(), G::DoF);
  for (int k = 0; k < G::DoF; ++k) {
    typename G::Tangent d = G::Tangent::Zero();
    d(k) = h;
    J.col(k) = (VecX(f(d)) - VecX(f(typename G::Tangent(-d)))) / (2.0 * h);
  }
  return J;
}

// Entries i.i.d. N(0, scale²).
inline MatX random_matrix(core::Rng& rng, Eigen::Index rows, Eigen::Index cols, double scale = 1.0) {
  MatX A(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) A(i, j) = scale * rng.normal();
  return A;
}

inline VecX random_vector(core::Rng& rng, Eigen::Index n, double scale = 1.0) {
  return random_matrix(rng, n, 1, scale);
}

// A B Bᵀ / n + min_eigenvalue I with B i.i.d. N(0, scale²): symmetric positive definite, smallest eigenvalue
// ≥ min_eigenvalue.
inline MatX random_spd(core::Rng& rng, Eigen::Index n, double scale = 1.0, double min_eigenvalue = 1e-3) {
  const MatX B = random_matrix(rng, n, n, scale);
  return B * B.transpose() / static_cast<double>(n) + min_eigenvalue * MatX::Identity(n, n);
}

// A tangent of group G with entries N(0, scale²); for SE(2)/SE(3) the translation part (ρ, the first 2 or 3
// entries) has scale `translation_scale` instead.
template <class G>
typename G::Tangent random_tangent(core::Rng& rng, double scale, double translation_scale) {
  typename G::Tangent xi;
  constexpr int nt = std::is_same_v<G, lie::SE2> ? 2 : std::is_same_v<G, lie::SE3> ? 3 : 0;
  for (int k = 0; k < G::DoF; ++k) xi(k) = (k < nt ? translation_scale : scale) * rng.normal();
  return xi;
}
template <class G>
typename G::Tangent random_tangent(core::Rng& rng, double scale = 1.0) {
  return random_tangent<G>(rng, scale, scale);
}

// exp of a random tangent: rotations with angle scale `rotation_scale` (radians), translations
// `translation_scale`.
template <class G>
G random_pose(core::Rng& rng, double rotation_scale = 1.0, double translation_scale = 1.0) {
  return G::exp(random_tangent<G>(rng, rotation_scale, translation_scale));
}

// Runs f and reports whether it threw an Ex whose message contains `needle`.
template <class Ex, class F>
bool throws_with(F&& f, std::string_view needle) {
  try {
    std::forward<F>(f)();
  } catch (const Ex& e) {
    return std::string_view(e.what()).find(needle) != std::string_view::npos;
  } catch (...) {
    return false;
  }
  return false;
}

// The message of the std::invalid_argument that f throws, or kNoThrow when it throws none (other exceptions
// propagate).
inline constexpr const char* kNoThrow = "<no throw>";
template <class F>
std::string message_of(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return kNoThrow;
}

inline bool contains(std::string_view s, std::string_view part) {
  return s.find(part) != std::string_view::npos;
}

}  // namespace keel::testkit
