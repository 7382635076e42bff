// What the 1D-world studies share: [params] read into World1DStudyOptions. Internal to engine/study/ch2; the
// studies are world1d_comparison.hpp, density_sweep.hpp and timing.hpp.
#pragma once

#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "study/ch2/world1d.hpp"

namespace keel::study::ch2 {

// [params] of the 1D-world studies: the world model (with counts), PCM's and RANSAC's thresholds
// γ = χ²₁ quantile of 1 − p (dof 1: the 1D world) from pcm_p and ransac_p, SCGP's options, the combinatorial
// search and the number of worlds.
[[nodiscard]] World1DStudyOptions read_world1d_study(const core::ConfigTable& p);

}  // namespace keel::study::ch2
