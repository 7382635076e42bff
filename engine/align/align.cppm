// keel.align — the curated facade of engine/align: trajectory alignment without data association (thesis
// ch. 3). Facade rules (docs/DESIGN.md) as every area.
module;
#include "align/align.hpp"
#include "align/certificate.hpp"
#include "align/hull.hpp"
#include "align/lp.hpp"
#include "align/sdp.hpp"
export module keel.align;

export namespace keel::align {
// problem, options, result
using keel::align::align;
using keel::align::AlignmentProblem;
using keel::align::AlignOptions;
using keel::align::AlignResult;
using keel::align::dissimilarity_matrix;
using keel::align::euclidean_dissimilarity;
using keel::align::feature_scales;
using keel::align::HullBackend;
using keel::align::HullCache;
using keel::align::HullOptions;
using keel::align::LpSettings;
using keel::align::Method;
using keel::align::method_from_string;
using keel::align::RegionOptions;
using keel::align::Rigid2;
using keel::align::RoundTrace;
using keel::align::standardize_features;
using keel::align::to_string;
using keel::align::Transform2;
// pieces: hulls, the octagon sectors of eq. 3.19, projection to SE(2)
using keel::align::approximately_valid;
using keel::align::boxes_exclude_sector;
using keel::align::kBarniAlpha1;
using keel::align::kBarniAlpha2;
using keel::align::kBarniDelta;
using keel::align::kSectorRowCount;
using keel::align::lower_hull_planes;
using keel::align::octagon_rows;
using keel::align::Plane;
using keel::align::project_to_rigid;
using keel::align::sector_rows;
using keel::align::singular_values;
// the LP itself, for custom rotation constraints
using keel::align::Box;
using keel::align::CsRow;
using keel::align::HullLp;
using keel::align::LpSolution;
using keel::align::LpStatus;
using keel::align::Parameterization;
// beyond the thesis: certified global optimum over SO(2)
using keel::align::Certificate;
using keel::align::CertificateOptions;
using keel::align::certify_rotation;
using keel::align::global_regions;
using keel::align::Regions;
using keel::align::rigid_objective;
// SOConvHull as an SDP (DSDP), the check of the LP with tangent cuts
using keel::align::SdpSolution;
using keel::align::so_conv_hull_sdp;
}  // namespace keel::align
