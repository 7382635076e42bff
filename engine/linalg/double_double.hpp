// Double-double arithmetic (Dekker 1971; Knuth's TwoSum; the exact product by a fused multiply-add; Joldes,
// Muller and Popescu, ACM TOMS 2017, for the algorithms and their error bounds), for the certificate of
// certified.cpp and sos/verify.cpp and the extended-precision factorization of sparse_cholesky.cpp. A value
// is hi + lo with |lo| ≤ u|hi| after every operation below (u = 2⁻⁵³). The rigour of the certificate never
// rests on the accuracy of div and sqrt: it rests on exact products and on the measured residual. Private to
// engine/pgo and sos.
#pragma once

#include <cmath>

namespace keel::linalg {

struct DD {
  double hi = 0.0, lo = 0.0;
};

// a·b exactly: a·b = p + fma(a, b, −p).
inline DD dd_prod(double a, double b) {
  const double p = a * b;
  return {p, std::fma(a, b, -p)};
}

// |s| ≥ |e| (or s = 0): s + e exactly as hi + lo.
inline DD dd_fast_two_sum(double s, double e) {
  const double h = s + e;
  return {h, e - (h - s)};
}

// x + y with an error below 4u²(|x| + |y|): TwoSum of the leading parts (exact), the trailing parts added in
// double, then FastTwoSum (exact).
inline DD dd_add(DD x, DD y) {
  const double s = x.hi + y.hi;
  const double bb = s - x.hi;
  const double e = ((x.hi - (s - bb)) + (y.hi - bb)) + (x.lo + y.lo);
  return dd_fast_two_sum(s, e);
}

// x · b with an error below 3u²|x||b|.
inline DD dd_scale(DD x, double b) {
  const DD p = dd_prod(x.hi, b);
  return dd_fast_two_sum(p.hi, p.lo + x.lo * b);
}

// x · y with an error below 7u²|x||y|.
inline DD dd_mul(DD x, DD y) {
  const DD p = dd_prod(x.hi, y.hi);
  return dd_fast_two_sum(p.hi, p.lo + (x.hi * y.lo + x.lo * y.hi));
}

// x / y (y ≠ 0), to about u² relative: one correction of the double quotient.
inline DD dd_div(DD x, DD y) {
  const double q = x.hi / y.hi;
  const DD r = dd_add(x, dd_scale(y, -q));  // x − q·y
  return dd_fast_two_sum(q, r.hi / y.hi);
}

// √x (x > 0), to about u² relative: one Newton correction of the double square root.
inline DD dd_sqrt(DD x) {
  const double s = std::sqrt(x.hi);
  const DD ss = dd_prod(s, s);
  const DD r = dd_add(x, DD{-ss.hi, -ss.lo});  // x − s²
  return dd_fast_two_sum(s, r.hi / (2.0 * s));
}

}  // namespace keel::linalg
