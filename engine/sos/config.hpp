// keel::sos — config readers of the chapter-4 experiments (one per options struct; errors located at file,
// table, key and line by core::ConfigTable).
#pragma once

#include <string>
#include <vector>

#include "core/config.hpp"
#include "graph/pose_graph.hpp"
#include "sos/certify.hpp"
#include "sos/studies.hpp"

namespace keel::sos {

// Keys: structure, solver, sdp_gap_tolerance, gap_tolerance, escalate, escalation_max_moments,
// polish_max_iterations.
[[nodiscard]] CertifyOptions read_certify_options(const core::ConfigTable& t);

// Keys: segment_length, stride, max_segments, random_extent, lm_max_iterations, and read_certify_options's.
[[nodiscard]] SegmentStudyOptions read_segment_study_options(const core::ConfigTable& t);

// A planar data set and its ground truth. Keys: dataset, graph_file, ground_truth_file and, for landmark
// data, ground_truth_landmarks_file (files resolved by keel::datasets::resolve_dataset_file).
struct PlanarDataset {
  graph::PoseGraph2D graph;
  std::vector<lie::SE2> truth;
  std::vector<lie::Vec2> truth_landmarks;
  std::string name;
};
[[nodiscard]] PlanarDataset load_planar_dataset(const core::ConfigTable& t);

// Keys: families (names), one [<table>.<name>] per family with poses, edge_probability, rotation_noise (rad),
// optional rotation_noise_kind ("normal", or "uniform": rotation measurements uniform on the circle),
// translation_noise, extent; trials (per family, one key for all); and read_certify_options's.
[[nodiscard]] ExactnessOptions read_exactness_options(const core::ConfigTable& t,
                                                      const std::string& families_table);

}  // namespace keel::sos
