// Readers of the chapter-3 options structs from an experiment's [params] (one reader per struct). Keys are
// read strictly (core::ConfigTable), the struct is validated, and a std::invalid_argument from validate()
// comes back as a core::ConfigError naming the file and table.
#pragma once

#include <vector>

#include "align/align.hpp"
#include "align/certificate.hpp"
#include "core/config.hpp"
#include "sim/alignment_world.hpp"
#include "sim/hull_world.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

// `reference_size`, `query_size`, `track_spacing`, `sample_spacing`, `feature_dim`, `bumps`, `bump_sigma`
// ([min, max] m), `feature_noise`, `position_noise`, `max_translation`, `max_rotation_deg`,
// `query_track_offset`, `query_random_heading`.
[[nodiscard]] sim::AlignmentWorldOptions read_alignment_world_options(const core::ConfigTable& t);

// `reference_length`, `reference_width`, `query_length`, `query_width`, `track_spacing`, `sample_spacing`,
// `standoff`, `feature_radius`, `max_translation`, `max_rotation_deg`, `dvl_range_noise`, `dvl_dropout`; the
// hull's shape keeps HullSurfaceOptions' defaults.
[[nodiscard]] sim::HullWorldOptions read_hull_world_options(const core::ConfigTable& t);

// `max_rounds`, `shrink`, `min_half_width`, `min_points`, `max_slope`, `matrix_bound`, `disc_tolerance`, and
// `depth_gate` when present (method: `proposed`; callers set it per method).
[[nodiscard]] AlignOptions read_align_options(const core::ConfigTable& t);

// `methods = ["proposed", "so_conv_hull", "symmetric", "affine"]` (any subset, in table order).
[[nodiscard]] std::vector<Method> read_methods(const core::ConfigTable& t);

// `methods`, the keys of read_align_options, `valid_tolerance`, and when present `certify` (with the keys of
// read_certificate_options) and `sdp_check_worlds`.
[[nodiscard]] ComparisonOptions read_comparison_options(const core::ConfigTable& t);

// `certificate_relative_gap`, `certificate_node_limit`, `certificate_initial_intervals`.
[[nodiscard]] CertificateOptions read_certificate_options(const core::ConfigTable& t);

}  // namespace keel::study::ch3
