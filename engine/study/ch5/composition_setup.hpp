// What the chapter-5 composition studies share: [params] read into a CompositionSetup (the Monte Carlo itself
// is simulate.hpp's). The studies: composition.hpp (Fig. 5.4), relative_pose.hpp (Figs. 5.5-5.6),
// unscented_ssc.hpp (Fig. 5.7), length_sweep.hpp (Fig. 5.8), noise_sweep.hpp (Fig. 5.9).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch5/simulate.hpp"

namespace keel::study::ch5 {

// [params] of a composition study: sigma_t, sigma_r, rho (eq. 5.41 and the AR(1) correlation), level (the one
// probability level scored, in levels[0]) and trajectories; also steps (N) when `with_steps`. Validated.
[[nodiscard]] CompositionSetup read_composition_setup(const core::ConfigTable& p, bool with_steps);

}  // namespace keel::study::ch5
