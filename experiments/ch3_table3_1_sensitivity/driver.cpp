// Beyond Table 3.1 (§3.7): the four alignment methods against feature noise and query size — thin driver
// over keel::align::run_alignment_study, one study per sweep point on the same worlds (stream_base 0).
import keel.core;
import keel.repro;
import keel.align;

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace core = keel::core;
namespace repro = keel::repro;
namespace align = keel::align;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto& p = ex.params();
    align::AlignmentStudyOptions o;
    o.world = align::read_alignment_world_options(p);
    o.compare = align::read_comparison_options(p);
    o.worlds = p.count("worlds");
    const auto noises = p.numbers("noise_values"), sizes = p.numbers("query_sizes");
    ex.params_done();
    if (noises.empty())
      throw core::ConfigError(fmt::format("{}: must not be empty", p.where("noise_values")));
    if (sizes.empty()) throw core::ConfigError(fmt::format("{}: must not be empty", p.where("query_sizes")));
    o.compare.certify = false;
    o.seed = ex.seed();
    o.stream_base = 0;  // every sweep point aligns the same worlds
    o.threads = ex.threads();
    const double base_noise = o.world.feature_noise, base_size = o.world.query_size;

    // One study per distinct (noise, size); the point the two sweeps share runs once.
    std::map<std::pair<double, double>, align::AlignmentStudyOutcome> done;
    std::size_t points = 0;
    {
      std::map<std::pair<double, double>, int> distinct;
      for (double n : noises) distinct[{n, base_size}] = 1;
      for (double s : sizes) distinct[{base_noise, s}] = 1;
      points = distinct.size();
    }
    core::Progress progress(ex.id(), points * o.worlds);
    auto study = [&](double noise, double size) -> const align::AlignmentStudyOutcome& {
      const auto key = std::make_pair(noise, size);
      auto it = done.find(key);
      if (it != done.end()) return it->second;
      align::AlignmentStudyOptions q = o;
      q.world.feature_noise = noise;
      q.world.query_size = size;
      return done.emplace(key, align::run_alignment_study(q, &progress)).first->second;
    };

    auto& r = ex.results();
    r.metric("worlds", static_cast<double>(o.worlds));
    r.series("noise.feature_noise", noises);
    r.series("size.query_size", sizes);
    repro::Figure f;
    f.file = ex.id() + ".png";
    f.title = fmt::format(
        "Beyond Table 3.1: sensitivity to feature noise (query {:g} m) and query size (noise {:g}), "
        "{} worlds per point",
        base_size, base_noise, o.worlds);
    f.rows = 2, f.cols = 3, f.width = 16.5, f.height = 9.0;
    const char* colors[] = {"tab:blue", "tab:orange", "tab:green", "tab:red"};
    const char* markers[] = {"o", "s", "^", "v"};
    struct Axis {
      std::string tag, what, xlabel;
      std::vector<double> values;
      bool noise;
    };
    for (const Axis& axis :
         {Axis{"noise", "feature noise", "feature noise std (field RMS 1)", noises, true},
          Axis{"size", "query size", "query square side (m), reference 60 m", sizes, false}}) {
      repro::Panel pr, pt, pv;
      pr.title = "median rotation SE vs " + axis.what, pt.title = "median translation SE vs " + axis.what;
      pv.title = "approx. valid rotations vs " + axis.what;
      pr.ylabel = "rad²", pt.ylabel = "m²", pv.ylabel = "% of worlds";
      pr.xlabel = pt.xlabel = pv.xlabel = axis.xlabel;
      pr.yscale = pt.yscale = "log";
      pt.legend = pv.legend = "none";
      pv.ylim = std::make_pair(-5.0, 105.0);
      for (std::size_t m = 0; m < o.compare.methods.size(); ++m) {
        const std::string name(align::to_string(o.compare.methods[m]));
        std::vector<double> rot, trans, valid;
        for (double v : axis.values) {
          const auto& out = axis.noise ? study(v, base_size) : study(base_noise, v);
          std::vector<double> rs, ts;
          double ok = 0;
          for (const auto& w : out.outcomes[m])
            rs.push_back(w.rot_se), ts.push_back(w.trans_se), ok += w.valid;
          rot.push_back(align::fenced_summary(rs).median);
          trans.push_back(align::fenced_summary(ts).median);
          valid.push_back(100.0 * ok / static_cast<double>(o.worlds));
        }
        r.series(name + "." + axis.tag + ".rot_se.median", rot);
        r.series(name + "." + axis.tag + ".trans_se.median", trans);
        r.series(name + "." + axis.tag + ".valid_rate", valid);
        for (auto* v : {&rot, &trans})
          for (double& x : *v) x = std::max(x, 1e-12);  // log axis
        pr.layers.push_back(repro::line_layer(axis.values, rot, name, colors[m % 4], markers[m % 4]));
        pt.layers.push_back(repro::line_layer(axis.values, trans, name, colors[m % 4], markers[m % 4]));
        pv.layers.push_back(repro::line_layer(axis.values, valid, name, colors[m % 4], markers[m % 4]));
      }
      f.panels.push_back(pr), f.panels.push_back(pt), f.panels.push_back(pv);
    }
    progress.finish();
    r.figure(f);
  });
}
