#include "sos/config.hpp"

#include <fmt/format.h>

#include "datasets/manifest.hpp"
#include "graph/io.hpp"
#include "graph/trajectory.hpp"

namespace keel::sos {

CertifyOptions read_certify_options(const core::ConfigTable& t) {
  CertifyOptions o;
  o.relaxation.structure = t.parse("structure", structure_from_string);
  o.relaxation.sdp.solver = t.parse("solver", convex::sdp_solver_from_string);
  o.relaxation.sdp.gap_tolerance = t.number("sdp_gap_tolerance");
  o.gap_tolerance = t.number("gap_tolerance");
  o.escalate = t.boolean("escalate");
  o.escalation_max_moments = static_cast<long>(t.integer("escalation_max_moments"));
  o.polish.max_iterations = static_cast<int>(t.integer("polish_max_iterations"));
  t.validate(o);
  return o;
}

SegmentStudyOptions read_segment_study_options(const core::ConfigTable& t) {
  SegmentStudyOptions o;
  o.segment_length = static_cast<int>(t.integer("segment_length"));
  o.stride = static_cast<int>(t.integer("stride"));
  o.max_segments = static_cast<int>(t.integer("max_segments"));
  o.random_extent = t.number("random_extent");
  o.lm.max_iterations = static_cast<int>(t.integer("lm_max_iterations"));
  o.sbsos = read_certify_options(t);
  t.validate(o);
  return o;
}

PlanarDataset load_planar_dataset(const core::ConfigTable& t) {
  PlanarDataset d;
  d.name = t.string("dataset");
  d.graph = graph::read_pose_graph_2d(datasets::resolve_dataset_file(d.name, t.string("graph_file")));
  d.truth = graph::read_poses_2d(datasets::resolve_dataset_file(d.name, t.string("ground_truth_file")));
  if (t.has("ground_truth_landmarks_file"))
    d.truth_landmarks = graph::read_landmarks_2d(
        datasets::resolve_dataset_file(d.name, t.string("ground_truth_landmarks_file")));
  if (d.truth.size() != d.graph.poses.size())
    throw core::ConfigError(fmt::format("{}: {} ground-truth poses for a graph of {} poses",
                                        t.where("ground_truth_file"), d.truth.size(), d.graph.poses.size()));
  return d;
}

ExactnessOptions read_exactness_options(const core::ConfigTable& t, const std::string& families_table) {
  ExactnessOptions o;
  o.certify = read_certify_options(t);
  const core::ConfigTable fams = t.table(families_table);
  const int trials = static_cast<int>(t.integer("trials"));
  for (const std::string& name : t.strings("families")) {
    if (!fams.has(name))
      throw core::ConfigError(fmt::format("{}: no [{}.{}] table", t.where("families"), families_table, name));
    const core::ConfigTable f = fams.table(name);
    ExactnessFamily fam;
    fam.name = name;
    fam.poses = static_cast<int>(f.integer("poses"));
    fam.edge_probability = f.number("edge_probability");
    if (f.string_or("rotation_noise_kind", "normal") == "uniform") fam.uniform_rotations = true;
    fam.rotation_noise = f.number("rotation_noise");
    fam.translation_noise = f.number("translation_noise");
    fam.extent = f.number("extent");
    fam.trials = trials;
    o.families.push_back(fam);
  }
  t.validate(o);
  return o;
}

}  // namespace keel::sos
