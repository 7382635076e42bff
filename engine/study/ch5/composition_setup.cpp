#include "study/ch5/composition_setup.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "lie/metrics.hpp"

namespace keel::study::ch5 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

CompositionSetup read_composition_setup(const core::ConfigTable& p, bool with_steps) {
  CompositionSetup s;
  if (with_steps) s.steps = static_cast<int>(p.count("steps"));
  s.sigma_t = p.number("sigma_t");
  s.sigma_r = p.number("sigma_r");
  s.rho = p.number("rho");
  s.levels = {p.number("level")};
  s.trajectories = p.count("trajectories");
  p.validate(s);
  return s;
}

}  // namespace keel::study::ch5
