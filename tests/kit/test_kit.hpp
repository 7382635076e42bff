// The shared test kit of every area's unit tests (docs/DESIGN.md "Naming and errors"): numerical Jacobians by
// central differences, random matrices, SPD and information matrices, tangents and poses drawn from
// keel::core::Rng (identical on every standard library, unlike std::normal_distribution), write-then-read
// round trips through memory or a file, and a check that a call throws a given message. Unit tests include it
// as "kit/test_kit.hpp"; it imports nothing (DESIGN rule 4).
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <filesystem>
#include <sstream>
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

// How random_information draws. Each form keeps the numbers its tests drew before the kit held it.
enum class InformationDraw {
  spread,  // D S D: S = random_spd(rng, N, 1, ½) (eigenvalues ≥ ½), then D diagonal with entries 10^U[−2, 4):
           // information over six orders of magnitude (scale and min_eigenvalue unused)
  correlated,  // (L Lᵀ)⁻¹, L = S C: C unit lower triangular with entries U[−0.3, 0.3] drawn row by row, then
               // S diagonal with entries scale · U[0.5, 1.5]: correlated, standard deviations around `scale`
  spd,         // scale · random_spd(rng, N, 1, min_eigenvalue) = scale · (B Bᵀ / N + min_eigenvalue · I)
};

// A random N × N information matrix (symmetric positive definite) drawn as `draw` says.
template <int N>
Eigen::Matrix<double, N, N> random_information(core::Rng& rng, InformationDraw draw = InformationDraw::spread,
                                               double scale = 1.0, double min_eigenvalue = 0.5) {
  using Mat = Eigen::Matrix<double, N, N>;
  switch (draw) {
    case InformationDraw::spread: {
      const Mat S = random_spd(rng, N, 1.0, 0.5);
      Eigen::Matrix<double, N, 1> d;
      for (int r = 0; r < N; ++r) d(r) = std::pow(10.0, rng.uniform(-2.0, 4.0));
      return d.asDiagonal() * S * d.asDiagonal();
    }
    case InformationDraw::correlated: {
      Mat C = Mat::Identity();
      for (int r = 0; r < N; ++r)
        for (int c = 0; c < r; ++c) C(r, c) = rng.uniform(-0.3, 0.3);
      Mat S = Mat::Zero();
      for (int k = 0; k < N; ++k) S(k, k) = scale * rng.uniform(0.5, 1.5);
      const Mat L = S * C;  // covariance L Lᵀ
      const Mat Li = L.template triangularView<Eigen::Lower>().solve(Mat::Identity());
      return Li.transpose() * Li;
    }
    case InformationDraw::spd:
      return scale * Mat(random_spd(rng, N, 1.0, min_eigenvalue));
  }
  throw std::invalid_argument("random_information: unknown InformationDraw");
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

// The round trip of a writer/reader pair through memory: write(std::ostream&) writes, read(std::istream&)
// reads what was written back; returns what read returns.
template <class Write, class Read>
auto round_trip(Write&& write, Read&& read) {
  std::ostringstream out;
  std::forward<Write>(write)(static_cast<std::ostream&>(out));
  std::istringstream in(out.str());
  return std::forward<Read>(read)(static_cast<std::istream&>(in));
}

// The same through the file `name` in the temporary directory: write(path) writes it, read(path) reads it
// back; the file is removed afterwards (also when read throws).
template <class Write, class Read>
auto round_trip_file(const std::string& name, Write&& write, Read&& read) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
  struct Remove {
    std::filesystem::path file;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(file, ec);
    }
  } remove{file};
  std::forward<Write>(write)(file);
  return std::forward<Read>(read)(file);
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
