// Unit tests of engine/align/sdp: SOConvHull as an SDP solved by DSDP against the alignment LP with tangent
// cuts.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "align/align.hpp"
#include "align/lp.hpp"
#include "align/sdp.hpp"
#include "align/test_problems.hpp"
#include "core/random.hpp"

using namespace keel::align;
using namespace keel::align::test;
using keel::core::Rng;

TEST_CASE("SOConvHull: the LP with tangent cuts equals the PSD form solved by DSDP") {
  for (std::uint64_t seed : {2u, 4u, 6u}) {
    auto p = exact_copy(11, 0.7 * static_cast<double>(seed), 0.3, -0.2, seed, 3);
    Rng rng(seed);
    for (auto& c : p.dissimilarity) c += 0.4 * rng.uniform();  // the relaxation now shrinks (c, s)
    AlignOptions o;
    const Regions reg = global_regions(p, o);
    LpSettings s = o.lp;
    s.disc_tolerance = 1e-9;
    HullLp lp(Parameterization::rotation_like, p.query_x, p.query_y, reg.planes, reg.boxes, s);
    const LpSolution cuts = lp.solve();
    REQUIRE(cuts.status == LpStatus::optimal);
    const SdpSolution sdp = so_conv_hull_sdp(p, reg);
    INFO("seed ", seed, " LP ", cuts.cost, " SDP ", sdp.cost);
    MESSAGE("seed ", seed, ": LP with cuts ", cuts.cost, " (c, s) = (", cuts.params[0], ", ", cuts.params[1],
            "), DSDP ", sdp.cost, " (", sdp.params[0], ", ", sdp.params[1], "), ", sdp.iterations,
            " iterations");
    CHECK(sdp.converged);
    CHECK(std::abs(sdp.cost - cuts.cost) <= 1e-6 * std::max(1.0, std::abs(cuts.cost)));
    CHECK(std::hypot(sdp.params[0], sdp.params[1]) <= 1 + 1e-6);
    CHECK(std::hypot(cuts.params[0], cuts.params[1]) <= 1 + 1e-9);
  }
}
