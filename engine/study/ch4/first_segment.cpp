#include "study/ch4/first_segment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/statistics.hpp"
#include "pgo/options.hpp"

namespace keel::study::ch4 {

using repro::Figure;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Fig. 4.1

FirstSegment::Outcome FirstSegment::run(const Options& o, const RunContext& context) {
  const PlanarDataset data = load_planar_dataset(o.data);
  Outcome out;
  out.options = o;
  out.segment = run_segments(data, o.study, context).segments.at(0);
  // The random start of the LM run (run_segment_study draws segment 0's from pgo seed `seed`), in the frame
  // of its pose 0 (as every other panel).
  const sos::Segment seg = sos::extract_segment(data.graph, 0, o.study.segment_length);
  pgo::Options start_options = o.study.lm;
  start_options.initial_guess = pgo::InitialGuess::random;
  start_options.seed = context.streams().seed();
  start_options.random_extent = o.study.random_extent;
  const pgo::Estimate2D start = pgo::initial_estimate(seg.graph, start_options);
  const lie::SE2 inv0 = start.poses.at(0).inverse();
  for (const auto& t : start.poses) out.start.poses.push_back(inv0 * t);
  for (const auto& l : start.landmarks) out.start.landmarks.push_back(inv0.act(l));
  return out;
}

void FirstSegment::record(Results& r, const Outcome& out) {
  const SegmentOutcome& s = out.segment;
  r.metric("poses", s.poses);
  r.metric("landmarks", s.landmarks);
  r.metric("landmark_measurements", s.landmark_measurements);
  r.metric("certified", s.status == core::SearchStatus::optimal ? 1.0 : 0.0);
  r.metric("certified_order", s.certified_order);
  r.metric("sbsos.gap", s.relative_gap);
  r.metric("rank_ratio", s.rank_ratio);
  for (const auto& m : segment_methods()) {
    const auto& e = s.*(m.member);
    const std::string k = m.key;
    r.under(k).metric("cost", e.cost);
    r.under(k).metric("trans_error", e.trans_error);
    r.under(k).metric("rot_error", e.rot_error);
    r.under(k).metric("landmark_error", e.landmark_error);
    r.under(k).timing("time_s", e.time_s);
  }
  r.check("SBSOS-SLAM's solution on the 430-pose segment is the global minimum (certified)",
          s.status == core::SearchStatus::optimal,
          fmt::format("gap {:.2g} (order {}), rank ratio {:.2g}", s.relative_gap, s.certified_order,
                      s.rank_ratio));
  // "Trapped in a local minimum" needs LM to have stopped on its own tolerance above the certified minimum: a
  // run cut off by its iteration cap above it is unfinished, not trapped.
  r.metric("lm_random.iterations", s.lm_random.iterations);
  r.metric("lm_random.converged", s.lm_random.converged ? 1.0 : 0.0);
  r.check("LM from a random initialization is trapped in a local minimum (Fig. 4.1 c)",
          above_sbsos(s, s.lm_random) && s.lm_random.converged,
          fmt::format("LM cost {:.6g} against the certified {:.6g}; LM {} after {} iterations",
                      s.lm_random.cost, s.sbsos.cost,
                      s.lm_random.converged ? "converged (met a tolerance)" : "stopped without converging",
                      s.lm_random.iterations));
  r.check("the segment holds 40 landmarks (Fig. 4.1 caption)", s.landmarks == 40,
          fmt::format("{} landmarks seen by poses 0–{}", s.landmarks, s.poses - 1), false);
}

std::vector<Figure> FirstSegment::figures(const Outcome& out) {
  const SegmentOutcome& s = out.segment;
  // Panels (a)–(d) of Fig. 4.1.
  auto panel = [](const std::string& title, const std::vector<lie::SE2>& poses,
                  const std::vector<lie::Vec2>& landmarks, const char* color) {
    Panel pn;
    pn.title = title, pn.xlabel = "x (m)", pn.ylabel = "y (m)", pn.aspect = "equal";
    std::vector<double> x, y, lx, ly;
    for (const auto& t : poses) x.push_back(t.translation().x()), y.push_back(t.translation().y());
    for (const auto& l : landmarks) lx.push_back(l.x()), ly.push_back(l.y());
    pn.layers.push_back(repro::line_layer(x, y, "poses", color));
    pn.layers.push_back(repro::scatter_layer(lx, ly, "landmarks", "k", 16, 1.0, "x"));
    pn.legend = "best";
    return pn;
  };
  Figure fig;
  fig.file = ".png";
  fig.title = fmt::format("Fig. 4.1: the first {} poses of CityTrees10000 and their {} landmarks", s.poses,
                          s.landmarks);
  fig.rows = 2, fig.cols = 2;
  fig.panels = {panel("(a) ground truth", s.truth, s.truth_landmarks, "0.4"),
                panel("(b) random initialization", out.start.poses, out.start.landmarks, "C1"),
                panel(fmt::format("(c) LM from (b): cost {:.5g}", s.lm_random.cost), s.lm_random.poses,
                      s.lm_random.landmarks, "C3"),
                panel(fmt::format("(d) SBSOS-SLAM, certified: cost {:.5g}", s.sbsos.cost), s.sbsos.poses,
                      s.sbsos.landmarks, "C0")};
  return {fig};
}

}  // namespace keel::study::ch4
