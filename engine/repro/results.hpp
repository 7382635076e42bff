// What an experiment run produces: scalar metrics, named series, claim checks, declarative figures (the
// figure contract is scripts/figure_schema.json; scripts/plot.py renders them) and provenance. Written as
// JSON with sorted keys to a temporary name and renamed (DESIGN convention 8). nlohmann::json stays inside
// results.cpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "repro/machine.hpp"

namespace keel::repro {

// One drawable layer of a panel; which fields matter depends on `type` ("line", "scatter", "segments",
// "hline", "vline"). Unset optional fields are omitted from the JSON.
struct Layer {
  std::string type = "line";
  std::vector<double> x, y;  // line, scatter
  std::vector<std::string>
      y_timings;  // line, scatter: instead of y, names of this run's timings (Results::timing)
                  // to plot; wall times stay out of the figure data, so result files remain
                  // identical across thread counts and timings are never diffed
  std::vector<double> x0, y0, x1, y1;  // segments
  std::vector<double> c;               // scatter/segments colour values
  std::optional<double> value;         // hline: y; vline: x
  std::string label, color, marker, linestyle, cmap;
  std::optional<double> size, alpha, linewidth, vmin, vmax;
};

// Layer builders for the common cases (drivers stay short).
Layer line_layer(std::vector<double> x, std::vector<double> y, std::string label, std::string color,
                 std::string marker = "", std::string linestyle = "");
Layer scatter_layer(std::vector<double> x, std::vector<double> y, std::string label, std::string color,
                    double size, double alpha = 1.0, std::string marker = ".");
Layer hline_layer(double y, std::string label, std::string color, std::string linestyle = "--");
// Outline of a histogram with unit-width bins centred on `bins` (frequencies `freq`, one per bin) as a step
// line.
Layer histogram_layer(const std::vector<double>& bins, const std::vector<double>& freq, std::string label,
                      std::string color);

// Empirical CDF of `values` as a line: sorted values against the fraction of values at or below each. Values
// below `floor` are drawn at `floor` (log axes cannot show zeros).
Layer ecdf_layer(std::vector<double> values, std::string label, std::string color, double floor = 0.0,
                 std::string linestyle = "");
struct Panel {
  std::string title, xlabel, ylabel;
  std::string xscale, yscale, aspect, legend, colorbar;
  std::optional<std::pair<double, double>> xlim, ylim;
  // Tick positions on x and, optionally, their labels (one per position): a categorical axis.
  std::vector<double> xticks;
  std::vector<std::string> xticklabels;
  std::vector<Layer> layers;
};

struct Figure {
  std::string file;  // file name under paper/figures/
  std::string title;
  int rows = 0, cols = 0;        // 0: one row of panels
  double width = 0, height = 0;  // inches; 0: the renderer's default (5.5 x 4.5 per panel)
  std::vector<Panel> panels;
};

struct Check {
  std::string name;  // the claim, in words
  bool passed = false;
  std::string detail;  // the measured numbers behind the verdict
  bool counted =
      true;  // false: true by construction of the method or setup; shown in the report, not counted
};

class Results;

// The part of a results key that comes from the data (a data set, a method, a noise level, a probability
// tag), one segment at a time: path("planted").under("n0100").key("time_s") is "planted.n0100.time_s". Keys
// are never joined by hand in a study (docs/DESIGN.md "Results keys"; CTest tiers.results_keys): the field is
// the literal at the call, the data parts go through under(). A segment must be non-empty, and a dot in it
// may only sit inside a number ("range1.5"): a segment that joins two names ("a.b") would hide a level, so it
// is refused (std::invalid_argument) rather than written.
class KeyPath {
 public:
  KeyPath() = default;
  KeyPath under(std::string_view segment) const;
  // Each of `levels`' segments below this path's (already checked when `levels` was built).
  KeyPath under(const KeyPath& levels) const { return KeyPath(prefix_ + levels.prefix_); }
  // "<prefix><field>"; the field is a literal at the call and may hold dots ("rot_se.median").
  std::string key(std::string_view field) const;
  const std::string& prefix() const { return prefix_; }  // "a.b." (with its trailing dot), "" at the root
  std::string name() const { return prefix_.empty() ? "" : prefix_.substr(0, prefix_.size() - 1); }  // "a.b"

 private:
  explicit KeyPath(std::string prefix) : prefix_(std::move(prefix)) {}
  std::string prefix_;
};

// A segment of a KeyPath (above) at the root.
KeyPath path(std::string_view segment);

// A view of Results whose keys all start with one KeyPath:
//   const auto m = r.under(dataset);  m.metric("cost", c);  m.under("odometry").metric("lower_bound", b);
class Scope {
 public:
  Scope under(std::string_view segment) const { return Scope(*r_, path_.under(segment)); }
  Scope under(const KeyPath& levels) const { return Scope(*r_, path_.under(levels)); }
  void metric(std::string_view field, double value) const;
  void series(std::string_view field, std::vector<double> values) const;
  void timing(std::string_view field, double time_s) const;
  void note(std::string_view field, const std::string& text) const;
  const KeyPath& path() const { return path_; }

 private:
  friend class Results;
  Scope(Results& r, KeyPath p) : r_(&r), path_(std::move(p)) {}
  Results* r_;
  KeyPath path_;
};

class Results {
 public:
  // The keys under "<segment>." or under a KeyPath (Scope).
  Scope under(std::string_view segment) { return Scope(*this, path(segment)); }
  Scope at(const KeyPath& p) { return Scope(*this, p); }
  void metric(const std::string& name, double value);
  void series(const std::string& name, std::vector<double> values);
  // A claim checked on our numbers. `counted = false` marks a claim that holds by construction (the report
  // shows it but leaves it out of the verdict).
  void check(const std::string& name, bool passed, const std::string& detail, bool counted = true);
  void figure(Figure f);
  void note(const std::string& key, const std::string& text);
  // Wall time of a phase in seconds. Reported, never diffed against baselines (machines differ).
  void timing(const std::string& name, double time_s);

  const std::map<std::string, double>& metrics() const { return metrics_; }
  const std::map<std::string, std::vector<double>>& all_series() const { return series_; }
  const std::vector<Check>& checks() const { return checks_; }

  struct Provenance {
    std::string id, profile, git_sha, compiler, config_file;
    std::uint64_t config_hash = 0, seed = 0;
    double wall_time_s = 0;
    unsigned threads = 0;
    std::size_t shards = 0;  // > 0: merged from this many partials (core/shard.hpp); wall time is the merge's
    // The machine of this run (of a merge: the merging machine's; its shards ran where the scheduler put
    // them).
    Machine machine;
  };
  // Writes the JSON document atomically (temporary file + rename), creating parent folders.
  void write(const std::filesystem::path& path, const Provenance& prov) const;

 private:
  std::map<std::string, double> metrics_;
  std::map<std::string, std::vector<double>> series_;
  std::vector<Check> checks_;
  std::vector<Figure> figures_;
  std::map<std::string, std::string> notes_;
  std::map<std::string, double> timings_;
};

// Writes `text` to `path` through a temporary file in the same folder and an atomic rename.
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

// Metric-name tag of a probability level: 0.95 -> "95", 0.999 -> "999", 0.5 -> "5".
std::string level_tag(double p);

// Rounds to 12 significant digits so committed baselines do not churn in the last bits (and prints
// compactly).
double round_significant(double v, int digits = 12);

}  // namespace keel::repro
