#include "study/ch5/pairs_vs_ssc.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/timing.hpp"
#include "cov/information.hpp"
#include "cov/marginal_covariance.hpp"
#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "pgo/optimize.hpp"

namespace keel::study::ch5 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Table 5.2

void PairsVsSsc::record(Results& r, const Outcome& s) {
  record_solved(r, s.solved);
  r.timing("monte_carlo", s.monte_carlo_time_s);
  const auto norm = repro::path("norm_cov_error");
  const auto lie_st = record_statistics(r, s, &PairRecord::normalized_error_lie, norm.under("lie"));
  const auto ssc_st = record_statistics(r, s, &PairRecord::normalized_error_ssc, norm.under("ssc"));
  (void)record_statistics(r, s, &PairRecord::normalized_error_ssc_raw_angles, norm.under("ssc_raw_angles"));
  const auto floor = record_statistics(r, s, &PairRecord::normalized_mc_floor, norm.under("mc_floor"));
  r.check(
      "the proposed relative pose is within 1.5× of the Monte-Carlo sampling floor (first order is "
      "adequate)",
      lie_st.mean < 1.5 * floor.mean,
      fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g}, sampling floor {:.4g}", lie_st.mean,
                  ssc_st.mean, floor.mean));
  std::size_t lie_lower = 0;
  for (const auto& rec : s.records) lie_lower += rec.normalized_error_lie < rec.normalized_error_ssc ? 1 : 0;
  r.check("the proposed relative pose has a several-fold lower normalized covariance error than SSC (≥ 3×)",
          ssc_st.mean > 3.0 * lie_st.mean,
          fmt::format("mean normalized ε: proposed {:.4g}, SSC {:.4g} (ratio {:.2f}; thesis 5.8)",
                      lie_st.mean, ssc_st.mean, ssc_st.mean / lie_st.mean));
  r.check("the proposed method is better than SSC for most pairs (> 50 %)", 2 * lie_lower > s.records.size(),
          fmt::format("{} of {} pairs", lie_lower, s.records.size()));
}

std::vector<Figure> PairsVsSsc::figures(const Outcome& s) {
  std::vector<Figure> out;
  for (int k : s.options.pairs.figure_offsets) {
    const auto sk = pair_statistics(s.records, &PairRecord::normalized_error_ssc, k);
    if (sk.count == 0) continue;
    const double vmax = sk.mean + 2.0 * sk.std;  // thesis: dark orange = 2 std above the mean (SSC)
    Figure f;
    f.file = fmt::format("_offset{}.png", k);
    f.title = fmt::format("Manhattan3500, pose pairs at offset {} (cf. Figs. 5.10–5.14 f–g)", k);
    f.width = 12.0;
    f.height = 5.5;
    f.panels.push_back(
        pair_panel(s, k, &PairRecord::normalized_error_lie, "(f) normalized ε, proposed", "Oranges", vmax));
    f.panels.push_back(
        pair_panel(s, k, &PairRecord::normalized_error_ssc, "(g) normalized ε, SSC", "Oranges", vmax));
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace keel::study::ch5
