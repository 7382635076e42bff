#include "study/ch2/world1d_study_common.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/world1d.hpp"
#include "study/ch2/config.hpp"

namespace keel::study::ch2 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

World1DStudyOptions read_world1d_study(const core::ConfigTable& p) {
  World1DStudyOptions o;
  o.world = read_world1d_options(p, true);
  o.pcm_gamma = pcm::consistency_threshold(p.number("pcm_p"), sim::kWorld1DDof);
  o.ransac_gamma = pcm::consistency_threshold(p.number("ransac_p"), sim::kWorld1DDof);
  o.scgp = read_scgp_options(p);
  o.combinatorial = p.parse("combinatorial", pcm::combinatorial_method_from_string);
  o.worlds = p.count("worlds");
  return o;
}

}  // namespace keel::study::ch2
