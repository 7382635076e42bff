#include "study/ch3/sweep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>

namespace keel::study::ch3 {

namespace {

std::vector<double> errors(const AlignmentStudyOutcome& st, std::size_t m, bool rot) {
  std::vector<double> v;
  for (const auto& w : st.outcomes[m]) v.push_back(rot ? w.rot_se : w.trans_se);
  return v;
}

}  // namespace

std::vector<std::pair<double, double>> read_sigma_ranges(const core::ConfigTable& p) {
  const std::vector<double> lo = p.numbers("field_sigma_min"), hi = p.numbers("field_sigma_max");
  if (lo.size() != hi.size())
    throw core::ConfigError(fmt::format("{}: {} values against {} in field_sigma_min",
                                        p.where("field_sigma_max"), hi.size(), lo.size()));
  std::vector<std::pair<double, double>> ranges;
  for (std::size_t k = 0; k < lo.size(); ++k) {
    if (!(lo[k] > 0 && lo[k] <= hi[k]))
      throw core::ConfigError(fmt::format("{}: range {} is [{}, {}]: need 0 < min <= max",
                                          p.where("field_sigma_min"), k, lo[k], hi[k]));
    ranges.emplace_back(lo[k], hi[k]);
  }
  return ranges;
}

sim::AlignmentWorldOptions world_of_point(sim::AlignmentWorldOptions w, const Sensitivity::Point& p) {
  w.feature_noise = p.noise;
  w.query_size = p.size;
  const auto second_moment = [](double a, double b) { return (a * a + a * b + b * b) / 3.0; };
  if (p.sigma_min != w.bump_sigma_min || p.sigma_max != w.bump_sigma_max) {
    w.bumps = static_cast<int>(std::lround(w.bumps * second_moment(w.bump_sigma_min, w.bump_sigma_max) /
                                           second_moment(p.sigma_min, p.sigma_max)));
    w.bump_sigma_min = p.sigma_min, w.bump_sigma_max = p.sigma_max;
  }
  return w;
}

std::size_t proposed_index(const AlignmentStudyOutcome& st) {
  const auto it = std::find(st.methods.begin(), st.methods.end(), Method::proposed);
  return it == st.methods.end() ? SIZE_MAX : static_cast<std::size_t>(it - st.methods.begin());
}

void add_paired_at(repro::PairedFamily& family, const repro::KeyPath& prefix,
                   const AlignmentStudyOutcome& st) {
  const std::size_t p = proposed_index(st);
  if (p == SIZE_MAX) return;
  for (std::size_t m = 0; m < st.methods.size(); ++m) {
    if (m == p) continue;
    const std::string other(align::to_string(st.methods[m]));
    family.add(prefix.under("rot_se").under(other).name(),
               repro::paired_median(errors(st, p, true), errors(st, m, true)));
    family.add(prefix.under("trans_se").under(other).name(),
               repro::paired_median(errors(st, p, false), errors(st, m, false)));
  }
}

PairedAtPoint paired_at(const repro::PairedFamily& family, const repro::KeyPath& prefix,
                        const AlignmentStudyOutcome& st) {
  PairedAtPoint r;
  const std::size_t p = proposed_index(st);
  if (p == SIZE_MAX) return r;
  for (std::size_t m = 0; m < st.methods.size(); ++m) {
    if (m == p) continue;
    r.others.emplace_back(align::to_string(st.methods[m]));
    r.rot.push_back(family.at(prefix.under("rot_se").under(r.others.back()).name()));
    r.trans.push_back(family.at(prefix.under("trans_se").under(r.others.back()).name()));
  }
  return r;
}

int count_if_paired(const std::vector<repro::PairedComparison>& v, bool lower) {
  return static_cast<int>(
      std::count_if(v.begin(), v.end(), [&](const auto& c) { return lower ? c.lower() : c.higher(); }));
}

}  // namespace keel::study::ch3
