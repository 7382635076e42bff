// Shared glue of the composition experiments (Figs. 5.4, 5.7, 5.8): the noise model and Monte-Carlo size of
// keel::lie::CompositionSetup read from [params]. Include after `import keel.core; import keel.lie;` (DESIGN
// rule 4).
#pragma once

namespace keel::experiments {

// sigma_t, sigma_r, rho (eq. 5.41 and the AR(1) correlation), level (the one probability level scored, in
// levels[0]) and trajectories; also steps (N) when `with_steps`.
inline keel::lie::CompositionSetup read_composition_setup(const keel::core::ConfigTable& p, bool with_steps) {
  keel::lie::CompositionSetup s;
  if (with_steps) s.steps = static_cast<int>(p.count("steps"));
  s.sigma_t = p.number("sigma_t");
  s.sigma_r = p.number("sigma_r");
  s.rho = p.number("rho");
  s.levels = {p.number("level")};
  s.trajectories = p.count("trajectories");
  return s;
}

}  // namespace keel::experiments
