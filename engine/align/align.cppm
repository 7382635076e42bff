// keel.align — the curated facade of engine/align: trajectory alignment without data association (thesis
// ch. 3). Facade rules (docs/DESIGN.md) as every area.
module;
#include "align/align.hpp"
#include "align/hull.hpp"
#include "align/lp.hpp"
export module keel.align;

export namespace keel::align {
// problem, options, result
using keel::align::align;
using keel::align::AlignmentProblem;
using keel::align::AlignOptions;
using keel::align::AlignResult;
using keel::align::dissimilarity_matrix;
using keel::align::euclidean_dissimilarity;
using keel::align::HullOptions;
using keel::align::LpSettings;
using keel::align::Method;
using keel::align::method_from_string;
using keel::align::RegionOptions;
using keel::align::Rigid2;
using keel::align::RoundTrace;
using keel::align::to_string;
using keel::align::Transform2;
// pieces: hulls, the octagon sectors of eq. 3.19, projection to SE(2)
using keel::align::approximately_valid;
using keel::align::kBarniAlpha1;
using keel::align::kBarniAlpha2;
using keel::align::kBarniDelta;
using keel::align::lower_hull_planes;
using keel::align::Plane;
using keel::align::project_to_rigid;
using keel::align::singular_values;
}  // namespace keel::align
