// Fig. 4.1 (§4.1, §4.6): the first 430 poses of CityTrees10000 and their landmarks — ground truth, LM's
// random initialization, LM's solution from it and the certified SBSOS-SLAM solution. Thin driver over
// keel::sos::run_segment_study (one segment) and keel::pgo::initial_estimate (the same random start LM used).
import keel.core;
import keel.repro;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.sos;

#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "common/sos_segments.hpp"

namespace core = keel::core;
namespace repro = keel::repro;
namespace sos = keel::sos;
namespace pgo = keel::pgo;

int main(int argc, char** argv) {
  return repro::experiment_main(argc, argv, [](repro::Experiment& ex) {
    const auto run = keel::experiments::run_segments(ex, "CityTrees10000, first segment");
    const sos::SegmentStudyOptions& o = run.options;
    const sos::SegmentOutcome& s = run.outcome.segments.at(0);
    // The random start of the LM run (run_segment_study draws segment 0's from pgo seed `seed`).
    const sos::Segment seg = sos::extract_segment(run.data.graph, 0, o.segment_length);
    pgo::Options start_options = o.lm;
    start_options.initial_guess = pgo::InitialGuess::random;
    start_options.seed = o.seed;
    start_options.random_extent = o.random_extent;
    const pgo::Estimate2D start = pgo::initial_estimate(seg.graph, start_options);

    auto& r = ex.results();
    r.metric("poses", s.poses);
    r.metric("landmarks", s.landmarks);
    r.metric("landmark_measurements", s.landmark_measurements);
    r.metric("certified", s.status == core::SearchStatus::optimal ? 1.0 : 0.0);
    r.metric("certified_order", s.certified_order);
    r.metric("sbsos.gap", s.relative_gap);
    r.metric("rank_ratio", s.rank_ratio);
    for (const auto& m : keel::experiments::segment_methods()) {
      const auto& e = s.*(m.member);
      const std::string k = m.key;
      r.metric(k + ".cost", e.cost);
      r.metric(k + ".trans_error", e.trans_error);
      r.metric(k + ".rot_error", e.rot_error);
      r.metric(k + ".landmark_error", e.landmark_error);
      r.timing(k + ".time_s", e.time_s);
    }
    r.check("SBSOS-SLAM's solution on the 430-pose segment is the global minimum (certified)",
            s.status == core::SearchStatus::optimal,
            fmt::format("gap {:.2g} (order {}), rank ratio {:.2g}", s.relative_gap, s.certified_order,
                        s.rank_ratio));
    r.check("LM from a random initialization is trapped in a local minimum (Fig. 4.1 c)",
            keel::experiments::above_sbsos(s, s.lm_random),
            fmt::format("LM cost {:.6g} against the certified {:.6g}", s.lm_random.cost, s.sbsos.cost));
    r.check("the segment holds 40 landmarks (Fig. 4.1 caption)", s.landmarks == 40,
            fmt::format("{} landmarks seen by poses 0–{}", s.landmarks, s.poses - 1), false);

    // Panels (a)–(d) of Fig. 4.1.
    auto panel = [](const std::string& title, const std::vector<keel::lie::SE2>& poses,
                    const std::vector<keel::lie::Vec2>& landmarks, const char* color) {
      repro::Panel pn;
      pn.title = title, pn.xlabel = "x (m)", pn.ylabel = "y (m)", pn.aspect = "equal";
      std::vector<double> x, y, lx, ly;
      for (const auto& t : poses) x.push_back(t.translation().x()), y.push_back(t.translation().y());
      for (const auto& l : landmarks) lx.push_back(l.x()), ly.push_back(l.y());
      pn.layers.push_back(repro::line_layer(x, y, "poses", color));
      pn.layers.push_back(repro::scatter_layer(lx, ly, "landmarks", "k", 16, 1.0, "x"));
      pn.legend = "best";
      return pn;
    };
    // The random start in the frame of its pose 0 (as every other panel).
    const keel::lie::SE2 inv0 = start.poses.at(0).inverse();
    std::vector<keel::lie::SE2> start_poses;
    std::vector<keel::lie::Vec2> start_landmarks;
    for (const auto& t : start.poses) start_poses.push_back(inv0 * t);
    for (const auto& l : start.landmarks) start_landmarks.push_back(inv0.act(l));
    repro::Figure fig;
    fig.file = "ch4_fig4_1_citytrees_430.png";
    fig.title = fmt::format("Fig. 4.1: the first {} poses of CityTrees10000 and their {} landmarks", s.poses,
                            s.landmarks);
    fig.rows = 2, fig.cols = 2;
    fig.panels = {panel("(a) ground truth", s.truth, s.truth_landmarks, "0.4"),
                  panel("(b) random initialization", start_poses, start_landmarks, "C1"),
                  panel(fmt::format("(c) LM from (b): cost {:.5g}", s.lm_random.cost), s.lm_random.poses,
                        s.lm_random.landmarks, "C3"),
                  panel(fmt::format("(d) SBSOS-SLAM, certified: cost {:.5g}", s.sbsos.cost), s.sbsos.poses,
                        s.sbsos.landmarks, "C0")};
    r.figure(fig);
  });
}
