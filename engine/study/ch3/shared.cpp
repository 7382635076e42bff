#include "study/ch3/shared.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/statistics.hpp"

namespace keel::study::ch3 {

std::vector<Row> table_rows(const AlignmentStudyOutcome& out, std::size_t worlds) {
  std::vector<Row> rows;
  for (std::size_t m = 0; m < out.methods.size(); ++m) {
    Row row;
    row.name = std::string(align::to_string(out.methods[m]));
    std::vector<double> times;
    for (const auto& w : out.outcomes[m]) {
      row.rot_se.push_back(w.rot_se), row.trans_se.push_back(w.trans_se), times.push_back(w.time_s);
      row.valid += w.valid;
    }
    row.valid *= 100.0 / static_cast<double>(worlds);
    row.rot = fenced_summary(row.rot_se);
    row.trans = fenced_summary(row.trans_se);
    const auto ts = fenced_summary(times);
    row.time_mean = ts.mean, row.time_median = ts.median;
    rows.push_back(std::move(row));
  }
  return rows;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return core::quantile_sorted(v, q);
}

double median_of(std::vector<double> v) { return quantile(std::move(v), 0.5); }

double fenced_std(std::vector<double> v) { return fenced_summary(std::move(v)).std; }

std::size_t common_rounds(const AlignmentStudyOutcome& out) {
  std::size_t n = SIZE_MAX;
  for (const auto& method : out.outcomes)
    for (const auto& w : method) n = std::min(n, w.round_scores.size());
  return n == SIZE_MAX ? 0 : n;
}

std::vector<double> per_world(const AlignmentStudyOutcome& out, std::size_t m, std::size_t r,
                              double EstimateScore::* field) {
  std::vector<double> v;
  for (const auto& w : out.outcomes[m])
    v.push_back((r == SIZE_MAX ? w.final_score : w.round_scores[r]).*field);
  return v;
}

double sector_offset(double theta) {
  const double eighth = kPi / 4;
  const double t = theta - eighth * std::floor(theta / eighth);  // θ mod 45°, in [0, π/4)
  return eighth / 2 - t;
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n, my /= n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxx > 0 ? sxy / sxx : 0.0;
}

std::string paired_text(const std::string& other, const repro::PairedComparison& c) {
  return fmt::format(
      "vs {}: {:+.3g} [{:+.3g}, {:+.3g}], {} lower / {} higher / {} tied{}, p = {:.2g}, Holm-adjusted "
      "{:.2g}{}",
      other, c.difference, c.low, c.high, c.below, c.above, c.ties,
      c.units == 0 ? "" : fmt::format(" of {}", c.units), c.p, c.adjusted_p,
      c.lower() ? ""
                : (c.higher() ? " (significantly higher)"
                              : " (not significant; no equivalence margin, so not \"equal\")"));
}

repro::PairedOptions paired_options(const std::vector<std::size_t>& blocks) {
  repro::PairedOptions o;
  o.blocks = blocks;
  return o;
}

std::vector<std::size_t> subset(const std::vector<std::size_t>& blocks,
                                const std::vector<std::size_t>& worlds) {
  if (blocks.empty()) return {};
  std::vector<std::size_t> r;
  for (std::size_t w : worlds) r.push_back(blocks[w]);
  return r;
}

void record_paired(const repro::Scope& key, const repro::PairedComparison& c, bool of_medians) {
  key.metric("difference", c.difference);
  if (of_medians) key.metric("difference_of_medians", c.difference_of_medians);
  key.metric("low", c.low);
  key.metric("high", c.high);
  key.metric("p", c.p);
  key.metric("adjusted_p", c.adjusted_p);
}

void record_family(repro::Results& r, const repro::PairedFamily& f) {
  r.metric("paired.family.size", static_cast<double>(f.size()));
  r.metric("paired.family.significant", static_cast<double>(f.significant()));
}

const double kOctagonMidpoint = std::cos(kPi / 8) / align::kBarniDelta;

}  // namespace keel::study::ch3
