// What a study needs from the run that calls it (docs/DESIGN.md "Studies"): its random streams, its threads,
// a progress bar, and trial loops that a sharded run (--slice / --merge, repro/shard.hpp) splits over
// processes. Every study has one shape,
//
//     struct Study {
//       struct Options { ...; static Options read(const core::ConfigTable& params); void validate() const; };
//       struct Outcome { Options options; ... };                  // self-describing: it holds its options
//       static Outcome run(const Options&, const RunContext&);
//       static void record(Results&, const Outcome&);             // metrics, series, claim checks, notes
//       static std::vector<Figure> figures(const Outcome&);       // see study_main for the file names
//     };
//
// and an experiment's driver is study_main<Study>: read the toml, run, record, draw.
#pragma once

#include <concepts>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/random.hpp"
#include "repro/experiment.hpp"
#include "repro/results.hpp"
#include "repro/shard.hpp"

namespace keel::repro {

class RunContext {
 public:
  // `threads` 0 = core::default_threads(); `progress` as core::Progress's `enabled` (-1: a terminal decides,
  // 0: off, 1: on); `label` names the bars (the experiment id).
  explicit RunContext(core::Streams streams, unsigned threads = 0, std::string label = "keel",
                      int progress = 0);

  [[nodiscard]] const core::Streams& streams() const { return streams_; }
  [[nodiscard]] unsigned threads() const { return threads_; }
  [[nodiscard]] const std::string& label() const { return label_; }

  // A progress bar over `total` units of this run's work.
  [[nodiscard]] core::Progress progress(std::size_t total) const {
    return core::Progress(label_, total, progress_);
  }
  // The same run on other streams (a sweep point on common random numbers, a named family).
  [[nodiscard]] RunContext with_streams(core::Streams streams) const;
  // The same run on fewer threads (work that must run alone, or is parallel inside).
  [[nodiscard]] RunContext with_threads(unsigned threads) const;

  // body(i) for the trials of [0, n) on this run's threads, slot i of each per-trial vector being trial i's
  // record (repro::save/load), advancing `progress` (may be null) once per trial. Sharded when the
  // experiment runs with --slice or --merge (repro/shard.hpp).
  template <class... Vectors>
  void trials(std::size_t n, const std::function<void(std::size_t)>& body, core::Progress* progress,
              Vectors&... per_trial) const {
    trial_loop(n, body, threads_, progress, per_trial...);
  }
  // The same with an explicit record: save(w, i) writes trial i's record, load(r, i) reads one into slot i.
  void trials(std::size_t n, const std::function<void(std::size_t)>& body,
              const std::function<void(Writer&, std::size_t)>& save,
              const std::function<void(Reader&, std::size_t)>& load, core::Progress* progress) const {
    trial_loop(n, body, save, load, threads_, progress);
  }

 private:
  core::Streams streams_;
  unsigned threads_;
  std::string label_;
  int progress_;
};

// The context of an experiment's run: its seed as the streams (base 0), its threads, its id as the label,
// progress bars when stderr is a terminal (KEEL_PROGRESS overrides).
[[nodiscard]] RunContext run_context(const Experiment& ex);

template <class S>
concept Study = requires(const core::ConfigTable& params, const typename S::Options& options,
                         const RunContext& context, Results& results, const typename S::Outcome& outcome) {
  { S::Options::read(params) } -> std::same_as<typename S::Options>;
  { S::run(options, context) } -> std::same_as<typename S::Outcome>;
  S::record(results, outcome);
  { S::figures(outcome) } -> std::same_as<std::vector<Figure>>;
};

// The main() of an experiment that runs one study: the options from [params] (every key read, no other),
// the run, its record, and its figures. A figure's file that begins with '.' or '_' is a suffix of the
// experiment's id (".png" → "<id>.png", "_errors.png" → "<id>_errors.png"); any other is taken as given (the
// thesis's own figure names, e.g. "ch4_fig4_2_citytrees_example.png").
template <Study S>
[[nodiscard]] int study_main(int argc, char** argv) {
  return experiment_main(argc, argv, [](Experiment& ex) {
    const typename S::Options options = S::Options::read(ex.params());
    ex.params_done();
    const typename S::Outcome outcome = S::run(options, run_context(ex));
    S::record(ex.results(), outcome);
    for (Figure& f : S::figures(outcome)) {
      if (f.file.empty() || f.file.front() == '.' || f.file.front() == '_') f.file = ex.id() + f.file;
      ex.results().figure(std::move(f));
    }
  });
}

}  // namespace keel::repro
