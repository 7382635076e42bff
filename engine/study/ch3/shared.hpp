// What the chapter-3 studies share: the Table 3.1 rows, robust summaries, the paired comparisons'
// records, colours and the octagon's geometry. Internal to engine/study/ch3 (not exported).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "align/align.hpp"
#include "core/statistics.hpp"
#include "repro/grading.hpp"
#include "repro/results.hpp"
#include "study/ch3/comparison.hpp"

namespace keel::study::ch3 {

inline constexpr const char* kColors[] = {"tab:blue", "tab:orange", "tab:green", "tab:red"};

// One method's column of Table 3.1 over the worlds.
struct Row {
  std::string name;
  FencedSummary rot, trans;
  double valid = 0, time_mean = 0, time_median = 0;
  std::vector<double> rot_se, trans_se;
};

std::vector<Row> table_rows(const AlignmentStudyOutcome& out, std::size_t worlds);

inline constexpr double kPi = 3.14159265358979323846;

double quantile(std::vector<double> v, double q);
double median_of(std::vector<double> v);
double fenced_std(std::vector<double> v);

// The number of rounds every world of a method ran (the schedule depends on the reference's size only, so
// this is every world's count on the Table 3.1 worlds).
std::size_t common_rounds(const AlignmentStudyOutcome& out);

// Per-world values of one score of method m at round r (r = SIZE_MAX: the final answer).
std::vector<double> per_world(const AlignmentStudyOutcome& out, std::size_t m, std::size_t r,
                              double EstimateScore::* field);

// The signed distance of the true rotation from the middle of its octagon sector, (22.5° − θ mod 45°) in
// radians: an estimate pulled to the edge's midpoint errs by exactly this.
double sector_offset(double theta);

// Least-squares slope of y on x (through their means); 0 when x does not vary.
double slope(const std::vector<double>& x, const std::vector<double>& y);

// "Proposed below X" by the paired rule (docs/GRADING.md): the text of one comparison and whether it holds.
std::string paired_text(const std::string& other, const repro::PairedComparison& c);

// The paired comparisons of one experiment's worlds: trials in spatial blocks where worlds share data.
repro::PairedOptions paired_options(const std::vector<std::size_t>& blocks);
std::vector<std::size_t> subset(const std::vector<std::size_t>& blocks,
                                const std::vector<std::size_t>& worlds);

// A comparison's numbers under its key (docs/GRADING.md "Paired orderings").
void record_paired(const repro::Scope& key, const repro::PairedComparison& c, bool of_medians);

// The family's size and how many of its comparisons are significant after Holm's correction.
void record_family(repro::Results& r, const repro::PairedFamily& f);

// Radius of the octagon's edge midpoints, cos(π/8)/δ (eq. 3.18 with Barni's δ): where an LP that slides
// along an edge toward its smallest |(c, s)| ends.
extern const double kOctagonMidpoint;

}  // namespace keel::study::ch3
