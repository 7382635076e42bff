// app::pcm on small synthetic two-robot graphs: the file pipeline (split_files → files → app::pcm) selects
// what the in-memory §2.6 pipeline selects; the merged graph carries exactly the χ² of the merged solve; bad
// candidates and options give located errors; the selection score against a count by hand.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/files.hpp"
#include "app/pcm.hpp"
#include "merge/merge.hpp"
#include "graph/g2o.hpp"
#include "graph/io.hpp"
#include "graph/parse_error.hpp"
#include "kit/test_kit.hpp"
#include "pcm/selection.hpp"
#include "pgo/optimize.hpp"
#include "sim/two_robot.hpp"
#include "sim/two_robot_test_graphs.hpp"

using namespace keel;
using keel::testkit::contains;
using keel::testkit::message_of;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("keel_app_test_" + name);
  fs::remove_all(d);
  return d;
}

}  // namespace

TEST_CASE("app::pcm on the files of split_files selects what the in-memory pipeline selects") {
  const auto syn = sim::testing::square_laps<lie::SE2>(3, 2, 41);
  app::SplitFilesOptions o;
  o.split = {0, 60, 120};
  o.candidates = sim::testing::small_candidate_options();
  o.seed = 5;
  const fs::path dir = scratch("split");
  const auto set = app::split_files(syn.graph, syn.truth, o, dir);

  // In memory: the scenario and candidates as generated.
  const auto scenario = sim::split_two_robots(syn.graph, syn.truth, o.split);
  const auto a = merge::solve_local(scenario.robot_a);
  const auto b = merge::solve_local(scenario.robot_b);
  const auto maps = merge::local_maps(a, b, set.candidates);
  const auto q = pcm::consistency_matrix(maps.a, maps.b, set.candidates);
  const double gamma = pcm::consistency_threshold(0.11, 3);
  const auto reference = pcm::select_pcm(q, gamma, pcm::CliqueAlgorithm::exact);

  // From the files.
  app::PcmOptions po;
  po.merge = true;
  std::vector<std::string> stages;
  const auto run =
      app::pcm(graph::read_pose_graph_2d(dir / "a.g2o"), graph::read_pose_graph_2d(dir / "b.g2o"),
               graph::read_g2o_edges_2d(dir / "candidates.g2o"), po,
               [&](std::string_view s) { stages.emplace_back(s); });
  CHECK(run.selection.selected == reference.selected);
  CHECK(run.gamma == gamma);
  REQUIRE(run.q.n == q.n);
  for (std::size_t k = 0; k < q.q.size(); ++k) CHECK(run.q.q[k] == doctest::Approx(q.q[k]).epsilon(1e-8));
  CHECK(stages.size() == 6);  // a, b, marginals, Q, clique, merge

  // The labels file marks the generated inliers, in order.
  const auto inlier = app::read_labels(dir / "labels.txt");
  REQUIRE(inlier.size() == set.labels.size());
  for (std::size_t k = 0; k < inlier.size(); ++k) CHECK(inlier[k] == set.labels[k].is_inlier());

  // The merged graph: both robots (b's ids shifted), both local graphs and the selected candidates, and at
  // the merged solution exactly the χ² the merged solve reports.
  const auto merged = app::merged_graph(run);
  CHECK(merged.poses.size() == 120);
  CHECK(merged.edges.size() ==
        scenario.robot_a.edges.size() + scenario.robot_b.edges.size() + run.selection.selected.size());
  pgo::Estimate2D at;
  at.poses = merged.poses;
  const auto e = pgo::evaluate(merged, at);
  CHECK(e.chi2 == doctest::Approx(run.merged->chi2).epsilon(1e-9));
  fs::remove_all(dir);
}

TEST_CASE("app::pcm in 3D, and merged_graph without a merged solve") {
  const auto syn = sim::testing::square_laps<lie::SE3>(3, 2, 43);
  const auto scenario = sim::split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  const auto set = sim::generate_candidates(scenario, sim::testing::small_candidate_options(), 7, 0);
  std::vector<graph::Edge3> edges;
  for (std::size_t k = 0; k < set.candidates.size(); ++k) {
    edges.push_back(
        {set.candidates[k].pose_a, set.candidates[k].pose_b, set.candidates[k].z, set.information[k], 0});
  }
  const auto run = app::pcm(scenario.robot_a, scenario.robot_b, edges);
  CHECK(run.q.dof == 6);
  CHECK(run.selection.search->proven_optimal());
  int inliers_kept = 0;
  for (int k : run.selection.selected)
    inliers_kept += set.labels[static_cast<std::size_t>(k)].is_inlier() ? 1 : 0;
  CHECK(inliers_kept >= 1);
  CHECK(contains(message_of([&] { (void)app::merged_graph(run); }), "the run has no merged solve"));
}

TEST_CASE("bad candidates and options are refused with the candidate and its line") {
  const auto syn = sim::testing::square_laps<lie::SE2>(2, 2, 45);
  const auto scenario = sim::split_two_robots(syn.graph, syn.truth, {0, 40, 80});
  graph::Edge2 e{3, 40, lie::SE2(1, 0, 0), lie::Mat3::Identity(), 7};
  CHECK(contains(message_of([&] { (void)app::pcm(scenario.robot_a, scenario.robot_b, {e}); }),
                 "candidate 0 (line 7): robot b has no pose 40 (it has 40 poses: 0 … 39)"));
  e.j = 2;
  e.i = -1;
  CHECK(contains(message_of([&] { (void)app::pcm(scenario.robot_a, scenario.robot_b, {e}); }),
                 "candidate 0 (line 7): robot a has no pose -1"));
  CHECK(contains(message_of([&] { (void)app::pcm(scenario.robot_a, scenario.robot_b, {}); }),
                 "inter-robot candidates: the candidate list is empty"));
  app::PcmOptions o;
  o.p = 0.0;
  e.i = 1;
  CHECK(contains(message_of([&] { (void)app::pcm(scenario.robot_a, scenario.robot_b, {e}, o); }),
                 "app::PcmOptions: p must be in (0, 1) (got 0)"));
}

TEST_CASE("the consistency step alone gives app::pcm's Q; the selection score counts what the labels say") {
  const auto syn = sim::testing::square_laps<lie::SE2>(3, 2, 47);
  const auto scenario = sim::split_two_robots(syn.graph, syn.truth, {0, 60, 120});
  const auto set = sim::generate_candidates(scenario, sim::testing::small_candidate_options(), 9, 0);
  std::vector<graph::Edge2> edges;
  for (std::size_t k = 0; k < set.candidates.size(); ++k) {
    edges.push_back(
        {set.candidates[k].pose_a, set.candidates[k].pose_b, set.candidates[k].z, set.information[k], 0});
  }
  const auto run = app::pcm(scenario.robot_a, scenario.robot_b, edges);
  // The first half of the pipeline alone gives the same Q, bit for bit.
  const auto c = app::consistency(scenario.robot_a, scenario.robot_b, edges);
  CHECK(c.q.q == run.q.q);
  // The score: counted by hand from the labels.
  std::vector<bool> inlier;
  for (const auto& l : set.labels) inlier.push_back(l.is_inlier());
  const auto s = app::score_selection(run.selection.selected, inlier);
  int tp = 0, inliers = 0;
  for (bool b : inlier) inliers += b ? 1 : 0;
  for (int k : run.selection.selected) tp += inlier[static_cast<std::size_t>(k)] ? 1 : 0;
  CHECK(s.true_positives == tp);
  CHECK(s.false_positives == static_cast<int>(run.selection.selected.size()) - tp);
  CHECK(s.tpr == doctest::Approx(static_cast<double>(tp) / inliers));
  CHECK(s.fpr == doctest::Approx(static_cast<double>(s.false_positives) /
                                 (static_cast<int>(inlier.size()) - inliers)));
  CHECK(contains(message_of([&] { (void)app::score_selection({5}, {true, false}); }),
                 "score_selection: candidate 5 has no label (2 labels)"));
}
