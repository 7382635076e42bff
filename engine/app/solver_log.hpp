// keel::app — where Ceres's own log goes. Ceres reports through glog (a residual block that evaluates to a
// non-finite value, a problem it refuses): uninitialized, glog prints every message to stderr, ~30 lines for
// one failed evaluation. route_solver_log() points glog at a callback (the `keel` command's stage lines) or
// nowhere (--quiet); no log file is ever written.
#pragma once

#include <functional>
#include <string_view>

namespace keel::app {

/// Receives one Ceres message: its severity ("warning", "error") and its text (possibly several lines).
using SolverLogSink = std::function<void(std::string_view severity, std::string_view message)>;

/// From now on, Ceres's warnings and errors go to `sink`; an empty sink drops them. Infos are dropped; a
/// fatal message still goes to stderr (glog aborts after it). Safe to call again (the last sink wins).
void route_solver_log(SolverLogSink sink);

}  // namespace keel::app
