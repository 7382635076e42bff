// Fig. 3.4 (§3.7): one simulated world of Table 3.1 and the four methods' estimates — thin driver over
// keel::align::run_alignment_study (one world) and keel::sim::make_alignment_world (the same seed and stream,
// so the same world, for the figure).
import keel.core;
import keel.repro;
import keel.sim;
import keel.align;

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ch3_fig3_4_example/report.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace sim = keel::sim;
namespace align = keel::align;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    align::AlignmentStudyOptions o;
    o.world = align::read_alignment_world_options(p);
    o.compare = align::read_comparison_options(p);
    o.stream_base = static_cast<std::uint64_t>(p.integer("world_index"));
    const double grid = p.number("field_grid_spacing");
    ex.params_done();
    if (!(grid > 0)) throw core::ConfigError(fmt::format("{}: must be > 0", p.where("field_grid_spacing")));
    o.worlds = 1;
    o.compare.certify = false;
    o.seed = ex.seed();
    o.threads = ex.threads();

    const auto out = align::run_alignment_study(o);
    const sim::AlignmentWorld w = sim::make_alignment_world(o.world, o.seed, o.stream_base);
    const auto shape = sim::lawn_mower(0, 0, o.world.query_size, o.world.query_size, o.world.track_spacing,
                                       o.world.sample_spacing);
    if (static_cast<std::size_t>(shape.tracks * shape.per_track) != w.query_x.size())
      throw std::logic_error("ch3_fig3_4_example: the query is not the lawn-mower of query_size");

    auto& r = ex.results();
    using Named = std::pair<const char*, double>;
    for (const auto& [key, v] :
         {Named{"world.theta", w.theta}, Named{"world.tx", w.tx}, Named{"world.ty", w.ty},
          Named{"reference_points", static_cast<double>(w.ref_x.size())},
          Named{"query_points", static_cast<double>(w.query_x.size())}})
      r.metric(key, v);
    for (std::size_t m = 0; m < out.methods.size(); ++m) {
      const auto& mo = out.outcomes[m][0];
      const std::string name(align::to_string(out.methods[m]));
      for (const auto& [key, v] :
           {Named{"rot_se", mo.rot_se}, Named{"trans_se", mo.trans_se}, Named{"valid", mo.valid ? 1.0 : 0.0},
            Named{"cost", mo.cost}, Named{"singular_min", mo.singular_min},
            Named{"singular_max", mo.singular_max}})
        r.metric(name + "." + key, v);
      r.timing(name + ".time_s", mo.time_s);
      if (out.methods[m] == align::Method::proposed)
        r.check(
            "the proposed estimate is an approximately valid rotation", mo.valid,
            fmt::format("singular values {:.4f}, {:.4f} (valid: within {} of 1, det > 0; the octagon is "
                        "within ±4.1 % of the circle)",
                        mo.singular_max, mo.singular_min, o.compare.valid_tolerance),
            o.compare.valid_tolerance <= 1.0 / align::kBarniDelta - 1.0);  // counted only if not guaranteed
    }

    r.figure(keel::experiments::fig3_4::example_figure(ex.id(), w, o, out, shape, grid));
  });
}
