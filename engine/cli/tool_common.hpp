// What the file commands share: stage lines on stderr, --quiet/--json, JSON output, and the solver options of
// `keel solve` and `keel marginals`. Included after `import keel.core; import keel.pgo; import keel.app;`
// (DESIGN rule 4).
#pragma once

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "commands.hpp"

namespace keel::cli {

using nlohmann::json;

// Stage lines on stderr: "keel solve [0.4 s] solving …".
class Stages {
 public:
  Stages(const char* command, bool quiet) : command_(command), quiet_(quiet), t0_(core::Clock::now()) {}
  void operator()(std::string_view stage) const {
    if (quiet_) return;
    fmt::print(stderr, "keel {} [{:.1f} s] {}\n", command_, elapsed(), stage);
    std::fflush(stderr);
  }
  double elapsed() const { return core::seconds_since(t0_); }
  // As an app::Progress.
  app::Progress progress() const {
    return [this](std::string_view s) { (*this)(s); };
  }

 private:
  const char* command_;
  bool quiet_;
  core::Clock::time_point t0_;
};

inline void add_common(CLI::App* c, Common& o) {
  c->add_flag("--quiet,-q", o.quiet, "no progress lines on stderr");
  c->add_flag("--json", o.json, "print one JSON document on stdout instead of the text summary");
}

inline void write_json(const std::filesystem::path& file, const json& j) {
  std::ofstream out(file);
  if (!out) throw std::invalid_argument(fmt::format("cannot write '{}'", file.string()));
  out << j.dump() << '\n';
  if (!out) throw std::runtime_error(fmt::format("writing '{}' failed", file.string()));
}

template <class M>
json matrix_json(const M& m) {
  json rows = json::array();
  for (int r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

inline json summary_json(const pgo::Summary& s) {
  return {{"termination", std::string(pgo::to_string(s.termination))},
          {"message", s.message},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost},
          {"final_chi2", s.final_chi2},
          {"normalized_chi2", s.normalized_chi2},
          {"iterations", s.iterations},
          {"total_time_s", s.total_time_s}};
}

// The arguments of `keel solve` and the solve of `keel marginals`.
struct SolveArgs {
  Common common;
  std::string file, out;
  app::SolveOptions options;  // pgo's defaults with only these fields set (app/solve.hpp)
};

inline void add_solve_options(CLI::App* c, SolveArgs& a) {
  auto& o = a.options;
  c->add_option("--init", o.init, "initial estimate: odometry, as-read (the file's vertices) or random")
      ->capture_default_str();
  c->add_option("--seed", o.seed, "seed of --init random")->capture_default_str();
  c->add_option("--robust", o.robust, "robust kernel on the loop closures: none, huber, cauchy or dcs")
      ->capture_default_str();
  c->add_option("--robust-param", o.robust_parameter, "Huber/Cauchy a or DCS φ")->capture_default_str();
  c->add_option("--threads", o.threads,
                "Ceres threads (the last bits of the result depend on it); 0 = all cores")
      ->capture_default_str();
  c->add_option("--max-iterations", o.max_iterations, "trust-region iterations")->capture_default_str();
}

inline void check_solved(const pgo::Summary& s) {
  if (s.termination == pgo::Termination::failure)
    throw CommandFailed(fmt::format("the solve failed: {}", s.message));
}

inline void print_solve_summary(const std::string& file, const pgo::Summary& s, std::size_t poses) {
  fmt::print("solved       {} ({} poses)\n", file, poses);
  fmt::print("termination  {} after {} iterations ({})\n", pgo::to_string(s.termination), s.iterations,
             s.message);
  fmt::print("cost         {:.10g} (initial {:.10g}); χ² {:.10g}; normalized χ² {:.6g}\n", s.final_cost,
             s.initial_cost, s.final_chi2, s.normalized_chi2);
  fmt::print("time         {:.3f} s\n", s.total_time_s);
}

}  // namespace keel::cli
