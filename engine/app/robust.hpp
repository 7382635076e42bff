// keel::app — the robust back end (merge/robust.hpp) on a user's graphs: the door `keel robust` and the
// Python module's `keel.robust` go through, so both give the same numbers. The pipeline and its types are
// merge's.
#pragma once

#include <vector>

#include "app/progress.hpp"
#include "graph/pose_graph.hpp"
#include "merge/robust.hpp"

namespace keel::app {

using merge::robust_gnc_from_string;
using merge::robust_residual_test_from_string;
using merge::robust_selector_from_string;
using merge::RobustCandidate;
using merge::RobustGnc;
using merge::RobustGncRound;
using merge::RobustGroup;
using merge::RobustOptions;
using merge::RobustResidualTest;
using merge::RobustRun;
using merge::RobustRun2;
using merge::RobustRun3;
using merge::RobustSelector;
using merge::to_string;  // of RobustSelector

/// merge::robust after the numeric check of every robot's graph and the inter-robot candidates
/// (files.hpp: the costs must be computable in double before a solver starts). Throws as merge::robust, and
/// std::invalid_argument for a number out of range.
[[nodiscard]] RobustRun2 robust(const std::vector<graph::PoseGraph2D>& robots,
                                const std::vector<graph::Edge2>& inter_robot = {},
                                const RobustOptions& options = {}, const Progress& progress = {});
[[nodiscard]] RobustRun3 robust(const std::vector<graph::PoseGraph3D>& robots,
                                const std::vector<graph::Edge3>& inter_robot = {},
                                const RobustOptions& options = {}, const Progress& progress = {});

}  // namespace keel::app
