#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "repro/results.hpp"
#include "repro/run.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
#include "sim/terrain.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

// Beyond Table 3.1: the methods against feature noise, query size and the feature field's length scale, one
// comparison per sweep point on the same worlds (streams from base 0 at every point).
struct Sensitivity {
  // One sweep point: feature noise, the query square's side, and the field's length scale (bump σ range, m).
  struct Point {
    double noise = 0, size = 0, sigma_min = 0, sigma_max = 0;
    [[nodiscard]] auto key() const { return std::tuple(noise, size, sigma_min, sigma_max); }
    bool operator<(const Point& o) const { return key() < o.key(); }
  };
  struct Options {
    AlignmentStudyOptions study;  // certify off; its world is the base point of every sweep
    std::vector<double> noises, sizes;
    std::vector<std::pair<double, double>> scales;  // bump σ ranges (m); may be empty
    static Options read(const core::ConfigTable& p);
    // The sweeps: axis 0 the noises, 1 the sizes, 2 the scales, each at the base values of the other two.
    [[nodiscard]] std::vector<Point> axis(int which) const;
    // The world options of a point. The bump count is scaled by E[σ²] of the base range over that of the
    // point's (E[σ²] = (a² + ab + b²)/3 for σ ~ U[a, b]), so every length scale covers the area alike.
    [[nodiscard]] sim::AlignmentWorldOptions world_at(const Point& p) const;
  };
  struct Outcome {
    Options options;
    // One comparison per distinct point; the base point the sweeps share runs once.
    std::map<Point, AlignmentStudyOutcome> points;
    [[nodiscard]] const AlignmentStudyOutcome& at(const Point& p) const;
  };
  static Outcome run(const Options& options, const repro::RunContext& context);
  static void record(repro::Results& results, const Outcome& outcome);
  static std::vector<repro::Figure> figures(const Outcome& outcome);
};

}  // namespace keel::study::ch3
