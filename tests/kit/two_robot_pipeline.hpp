// The two-robot fixture of the map-merging tests (engine/merge/merge_test.cpp,
// engine/study/ch2/merge_eval_test.cpp): `laps` square laps split between two robots at 20 and 40 poses a
// lap, each robot's map solved once (§2.6 step i).
#pragma once

#include <cstdint>

#include "merge/merge.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"

namespace keel::testkit {

template <class G>
struct TwoRobotPipeline {
  sim::TwoRobotScenario<G> scenario;
  merge::LocalSolution<G> a, b;
};

template <class G>
TwoRobotPipeline<G> two_robot_pipeline(std::uint64_t seed, int laps = 3) {
  const auto syn = sim::testing::square_laps<G>(laps, 2, seed);
  TwoRobotPipeline<G> p;
  p.scenario = sim::split_two_robots(syn.graph, syn.truth, {0, 20 * laps, 40 * laps});
  p.a = merge::solve_local(p.scenario.robot_a);
  p.b = merge::solve_local(p.scenario.robot_b);
  return p;
}

}  // namespace keel::testkit
