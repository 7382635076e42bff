// The linear program of convex/lp.hpp on COIN-OR CLP: a vertex optimum by hand, warm re-solves after rows are
// added, changed and deleted, fixed columns, infeasibility, and bad inputs.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "convex/lp.hpp"
#include "kit/test_kit.hpp"

using namespace keel::convex;
using keel::testkit::message_of;

namespace {
// max x + y (min −x − y) over x, y ≥ 0 with x + 2y ≤ 4 and 3x + y ≤ 6: the vertex (8/5, 6/5), value −14/5.
Lp two_by_two(bool dantzig) {
  LpOptions o;
  o.dantzig_dual_pricing = dantzig;
  Lp lp({-1.0, -1.0}, {0.0, 0.0}, {kLpInfinity, kLpInfinity}, o);
  LpRows rows;
  rows.add(-kLpInfinity, 4.0, {0, 1}, {1.0, 2.0});
  rows.add(-kLpInfinity, 6.0, {0, 1}, {3.0, 1.0});
  CHECK(lp.add_rows(rows) == 0);
  return lp;
}
}  // namespace

TEST_CASE("a vertex optimum by hand, and warm re-solves after the rows change") {
  for (bool dantzig : {false, true}) {
    Lp lp = two_by_two(dantzig);
    REQUIRE(lp.solve() == LpStatus::optimal);
    CHECK(lp.columns() == 2);
    CHECK(lp.rows() == 2);
    CHECK(lp.objective() == doctest::Approx(-14.0 / 5.0));
    CHECK(lp.solution()[0] == doctest::Approx(8.0 / 5.0));
    CHECK(lp.solution()[1] == doctest::Approx(6.0 / 5.0));
    // A cut y ≤ 1 moves the optimum to (5/3, 1).
    LpRows cut;
    cut.add(-kLpInfinity, 1.0, {1}, {1.0});
    CHECK(lp.add_rows(cut) == 2);
    REQUIRE(lp.solve() == LpStatus::optimal);
    CHECK(lp.objective() == doctest::Approx(-8.0 / 3.0));
    CHECK(lp.solution()[0] == doctest::Approx(5.0 / 3.0));
    // The cut changed in place to 2x + y ≤ 3 (a coefficient and a bound): x + 2y ≤ 4 and 2x + y ≤ 3 meet at
    // the new optimum (2/3, 5/3).
    lp.set_coefficient(2, 0, 2.0);
    lp.set_row_bounds(2, -kLpInfinity, 3.0);
    REQUIRE(lp.solve() == LpStatus::optimal);
    CHECK(lp.objective() == doctest::Approx(-7.0 / 3.0));
    // Without the cut, the first optimum again.
    lp.delete_rows({2});
    REQUIRE(lp.solve() == LpStatus::optimal);
    CHECK(lp.objective() == doctest::Approx(-14.0 / 5.0));
    // A fixed column: x = 1 leaves y = min((4 − 1)/2, 6 − 3) = 1.5.
    lp.set_column_bounds(0, 1.0, 1.0);
    REQUIRE(lp.solve() == LpStatus::optimal);
    CHECK(lp.solution()[1] == doctest::Approx(1.5));
    CHECK(lp.iterations() >= 0);
  }
}

TEST_CASE("an infeasible LP is reported as such; bad inputs give clear errors") {
  Lp lp = two_by_two(true);
  LpRows far;
  far.add(10.0, kLpInfinity, {0, 1}, {1.0, 1.0});  // x + y ≥ 10 cannot meet x + 2y ≤ 4 with y ≥ 0
  lp.add_rows(far);
  CHECK(lp.solve() == LpStatus::infeasible);
  CHECK(message_of([] { Lp bad({1.0, 2.0}, {0.0}, {1.0, 1.0}); }).find("2 costs but 1 lower and 2 upper") !=
        std::string::npos);
  LpRows rows;
  CHECK(message_of([&] { rows.add(0.0, 1.0, {0, 1}, {1.0}); }).find("2 columns but 1 values") !=
        std::string::npos);
}
