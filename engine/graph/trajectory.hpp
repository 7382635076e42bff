// keel::graph — plain pose lists: the derived ground-truth files of shared/datasets/*/derived/ and TUM
// trajectories.
//
//   poses 2D      `id x y theta`                 (derived/*_groundtruth_poses.txt, 2D)
//   landmarks 2D  `id x y`                       (derived/cityTrees10000_groundtruth_landmarks.txt)
//   poses 3D      `id x y z qx qy qz qw`         (derived/sphere2500_groundtruth_poses.txt; Hamilton
//   quaternion) pose list 2D  `x y theta`, the line order is the id (vertigo's *_nodes_groundTruth.dat) TUM
//   `timestamp tx ty tz qx qy qz qw` (evo, TUM RGB-D tools); written with timestamp = pose index and 2D
//                 poses embedded in the plane z = 0 (rotation about z).
// Ids must be contiguous from 0 (any order, each once); everything else as strict as the graph readers
// (ParseError with file, line, field).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "graph/pose_graph.hpp"

namespace keel::graph {

std::vector<SE2> read_poses_2d(const std::filesystem::path& file);
std::vector<SE2> read_poses_2d(std::istream& in, const std::string& name);
std::vector<Vec2> read_landmarks_2d(const std::filesystem::path& file);
std::vector<Vec2> read_landmarks_2d(std::istream& in, const std::string& name);
std::vector<SE3> read_poses_3d(const std::filesystem::path& file);
std::vector<SE3> read_poses_3d(std::istream& in, const std::string& name);
std::vector<SE2> read_pose_list_2d(const std::filesystem::path& file);
std::vector<SE2> read_pose_list_2d(std::istream& in, const std::string& name);

/// %.17g; theta in (−π, π]; quaternions with w ≥ 0.
void write_poses_2d(const std::vector<SE2>& poses, std::ostream& out);
void write_poses_2d(const std::vector<SE2>& poses, const std::filesystem::path& file);
void write_landmarks_2d(const std::vector<Vec2>& landmarks, std::ostream& out);
void write_landmarks_2d(const std::vector<Vec2>& landmarks, const std::filesystem::path& file);
void write_poses_3d(const std::vector<SE3>& poses, std::ostream& out);
void write_poses_3d(const std::vector<SE3>& poses, const std::filesystem::path& file);

struct TumPose {
  double timestamp = 0.0;
  SE3 pose;
};

/// One line per pose, timestamp = index, %.17g, quaternion (qx qy qz qw) with w ≥ 0; a 2D pose (x, y, θ)
/// becomes t = (x, y, 0), q = (0, 0, sin θ/2, cos θ/2).
void write_tum(const std::vector<SE2>& poses, std::ostream& out);
void write_tum(const std::vector<SE3>& poses, std::ostream& out);
void write_tum(const std::vector<SE2>& poses, const std::filesystem::path& file);
void write_tum(const std::vector<SE3>& poses, const std::filesystem::path& file);
std::vector<TumPose> read_tum(const std::filesystem::path& file);
std::vector<TumPose> read_tum(std::istream& in, const std::string& name);

}  // namespace keel::graph
