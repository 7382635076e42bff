// The shared main() of every experiment driver. A driver is thin (DESIGN convention 6):
//
//   import keel.core;
//   int main(int argc, char** argv) {
//     return keel::repro::experiment_main(argc, argv, [](keel::repro::Experiment& ex) {
//       const auto n = ex.params().integer("steps");   // strict: missing/wrong type -> error naming file and
//       key ex.params_done();                               // unknown keys -> error before any long work
//       ex.results().metric("x", compute(n, ex.seed(), ex.threads()));
//     });
//   }
//
// Command line: --config experiments/<id>/experiment.toml [--profile quick|full] [--out
// results/<id>/latest.json]
//               [--threads N]. Exit codes: 0 ok, 1 the run failed, 2 bad command line or configuration.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "repro/experiment_config.hpp"
#include "repro/results.hpp"

namespace keel::repro {

class Experiment {
 public:
  Experiment(ExperimentConfig config, unsigned threads);
  const ExperimentConfig& config() const { return config_; }
  const ConfigTable& params() const { return config_.params; }
  // Rejects [params]/[profiles.*] keys the driver did not read. Called again after the body returns.
  void params_done() const { config_.params.finish(); }
  Results& results() { return results_; }
  const Results& results() const { return results_; }
  unsigned threads() const { return threads_; }
  std::uint64_t seed() const { return config_.seed; }
  const std::string& profile() const { return config_.profile; }
  const std::string& id() const { return config_.id; }

 private:
  ExperimentConfig config_;
  unsigned threads_;
  Results results_;
};

using ExperimentBody = std::function<void(Experiment&)>;

[[nodiscard]] int experiment_main(int argc, char** argv, const ExperimentBody& body);

// The standard output of a shell command, trailing newlines removed ("" when it cannot run).
std::string run_capture(const std::string& cmd);

// "abc1234" or "abc1234-dirty" for the repository holding `path`; "unknown" outside git.
std::string git_describe(const std::string& path);

// Whether `sha` (as git_describe wrote it) names a commit: not "-dirty", not "unknown". Only such a result
// can be traced to the code that made it, so only such a result is blessed (docs/GRADING.md "Baselines").
bool clean_commit(const std::string& sha);

// Whether the engine, the build files or experiments/<id> differ between commit `sha` (as git_describe wrote
// it) and the working tree now. A "-dirty" or unknown sha counts as changed: such a result cannot be tied to
// committed code. `base` (a variant's params_from, or empty) adds experiments/<base>, whose driver and
// parameters the variant uses.
bool code_changed_since(const std::string& sha, const std::string& id, const std::string& base = "");

}  // namespace keel::repro
