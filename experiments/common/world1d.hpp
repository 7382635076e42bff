// Shared glue of the 1D-world experiments (Fig. 2.2 and its density sweep): keel::eval::World1DStudyOptions
// read from [params]. Include after `import keel.core; import keel.pcm; import keel.eval;` (DESIGN rule 4).
#pragma once

namespace keel::experiments {

// The world model (with counts), PCM's and RANSAC's thresholds γ = χ²₁ quantile of 1 − p (dof 1: the 1D
// world) from pcm_p and ransac_p, SCGP's options, the combinatorial search and the number of worlds.
inline keel::eval::World1DStudyOptions read_world1d_study(const keel::core::ConfigTable& p) {
  keel::eval::World1DStudyOptions o;
  o.world = keel::eval::read_world1d_options(p, true);
  o.pcm_gamma = keel::pcm::consistency_threshold(p.number("pcm_p"), 1);
  o.ransac_gamma = keel::pcm::consistency_threshold(p.number("ransac_p"), 1);
  o.scgp = keel::eval::read_scgp_options(p);
  o.combinatorial = p.parse("combinatorial", keel::eval::combinatorial_method_from_string);
  o.worlds = p.count("worlds");
  return o;
}

}  // namespace keel::experiments
