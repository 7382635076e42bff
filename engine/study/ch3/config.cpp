#include "study/ch3/config.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace keel::study::ch3 {

using namespace keel::align;

namespace {

constexpr double kPi = 3.14159265358979323846;

int read_int(const core::ConfigTable& t, std::string_view key) { return static_cast<int>(t.integer(key)); }

}  // namespace

sim::AlignmentWorldOptions read_alignment_world_options(const core::ConfigTable& t) {
  sim::AlignmentWorldOptions w;
  w.reference_size = t.number("reference_size");
  w.query_size = t.number("query_size");
  w.track_spacing = t.number("track_spacing");
  w.sample_spacing = t.number("sample_spacing");
  w.feature_dim = read_int(t, "feature_dim");
  w.bumps = read_int(t, "bumps");
  const auto sigma = t.numbers("bump_sigma");
  if (sigma.size() != 2)
    throw core::ConfigError(fmt::format("{}: expected [min, max]", t.where("bump_sigma")));
  w.bump_sigma_min = sigma[0], w.bump_sigma_max = sigma[1];
  w.feature_noise = t.number("feature_noise");
  w.position_noise = t.number("position_noise");
  w.max_translation = t.number("max_translation");
  w.max_rotation = t.number("max_rotation_deg") * kPi / 180.0;
  w.query_track_offset = t.boolean("query_track_offset");
  w.query_random_heading = t.boolean("query_random_heading");
  t.validate(w);
  return w;
}

sim::HullWorldOptions read_hull_world_options(const core::ConfigTable& t) {
  sim::HullWorldOptions w;
  w.reference_length = t.number("reference_length");
  w.reference_width = t.number("reference_width");
  w.query_length = t.number("query_length");
  w.query_width = t.number("query_width");
  w.track_spacing = t.number("track_spacing");
  w.sample_spacing = t.number("sample_spacing");
  w.standoff = t.number("standoff");
  w.feature_radius = t.number("feature_radius");
  w.max_translation = t.number("max_translation");
  w.max_rotation = t.number("max_rotation_deg") * kPi / 180.0;
  w.dvl.range_noise = t.number("dvl_range_noise");
  w.dvl.dropout = t.number("dvl_dropout");
  t.validate(w);
  return w;
}

AlignOptions read_align_options(const core::ConfigTable& t) {
  AlignOptions o;
  o.region.max_rounds = read_int(t, "max_rounds");
  o.region.shrink = t.number("shrink");
  o.region.min_half_width = t.number("min_half_width");
  o.region.min_points = t.count("min_points");
  o.hull.max_slope = t.number("max_slope");
  o.lp.matrix_bound = t.number("matrix_bound");
  o.disc_tolerance = t.number("disc_tolerance");
  if (t.has("depth_gate")) o.depth_gate = t.number("depth_gate");
  t.validate(o);
  return o;
}

std::vector<Method> read_methods(const core::ConfigTable& t) {
  std::vector<Method> out;
  for (const auto& name : t.strings("methods")) {
    try {
      out.push_back(method_from_string(name));
    } catch (const std::invalid_argument& e) {
      throw core::ConfigError(fmt::format("{}: {}", t.where("methods"), e.what()));
    }
  }
  if (out.empty()) throw core::ConfigError(fmt::format("{}: no method", t.where("methods")));
  return out;
}

ComparisonOptions read_comparison_options(const core::ConfigTable& t) {
  ComparisonOptions c;
  c.methods = read_methods(t);
  c.align = read_align_options(t);
  c.valid_tolerance = t.number("valid_tolerance");
  if (t.has("certify")) {
    c.certify = t.boolean("certify");
    c.certificate = read_certificate_options(t);
  }
  if (t.has("sdp_check_worlds")) c.sdp_check_worlds = static_cast<std::size_t>(t.integer("sdp_check_worlds"));
  t.validate(c);
  return c;
}

CertificateOptions read_certificate_options(const core::ConfigTable& t) {
  CertificateOptions c;
  c.relative_gap = t.number("certificate_relative_gap");
  c.node_limit = t.count("certificate_node_limit");
  c.initial_intervals = read_int(t, "certificate_initial_intervals");
  t.validate(c);
  return c;
}

}  // namespace keel::study::ch3
