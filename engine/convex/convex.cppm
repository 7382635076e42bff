// keel.convex — the curated facade of engine/convex (tier "algorithms", docs/DESIGN.md "Tiers"): one
// semidefinite program form solved by DSDP or SDPA and checked here, and a linear program kept between solves
// on CLP. Facade rules as every area.
module;
#include "convex/lp.hpp"
#include "convex/sdp.hpp"
export module keel.convex;

export namespace keel::convex {
// semidefinite programs
using keel::convex::check_sdp;
using keel::convex::dense_blocks;
using keel::convex::LpEntry;
using keel::convex::Sdp;
using keel::convex::sdp_solver_from_string;
using keel::convex::SdpCheck;
using keel::convex::SdpEntry;
using keel::convex::SdpSettings;
using keel::convex::SdpSolution;
using keel::convex::SdpSolver;
using keel::convex::solve_sdp;
using keel::convex::to_string;
// linear programs
using keel::convex::kLpInfinity;
using keel::convex::Lp;
using keel::convex::LpOptions;
using keel::convex::LpRows;
using keel::convex::LpStatus;
}  // namespace keel::convex
