#include "repro/experiment.hpp"
#include "repro/machine.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <optional>
#include <string_view>
#include <vector>
#include <exception>
#include <filesystem>
#include <iostream>

#include "core/blas.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "repro/shard.hpp"

namespace keel::repro {

using core::ConfigError;
using core::default_threads;
using core::format_duration;

Experiment::Experiment(ExperimentConfig config, unsigned threads)
    : config_(std::move(config)), threads_(threads) {}

std::string run_capture(const std::string& cmd) {
  std::string out;
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    ::pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void usage(const char* prog) {
  fmt::print(stderr,
             "usage: {} --config experiments/<id>/experiment.toml [--profile quick|full] "
             "[--out results/<id>/latest.json] [--threads N]\n"
             "       [--slice k/N --partial FILE]   run shard k of N of the trials, write a partial file\n"
             "       [--merge FILE...]              merge the N partial files into the results\n",
             prog);
}

}  // namespace

std::string git_describe(const std::string& path) {
  const std::string dir = shell_quote(path.empty() ? "." : path);
  std::string sha = run_capture(fmt::format("git -C {} rev-parse --short=12 HEAD 2>/dev/null", dir));
  if (sha.empty()) return "unknown";
  // Pathspecs from the repository root (":/"), untracked sources included: any change to the engine or the
  // experiments since HEAD makes the result "-dirty".
  const std::string dirty =
      run_capture(fmt::format("git -C {} status --porcelain --untracked-files=normal -- ':/engine' "
                              "':/experiments' ':/CMakeLists.txt' "
                              "':/cmake' 2>/dev/null",
                              dir));
  return dirty.empty() ? sha : fmt::format("{}-dirty", sha);
}

bool clean_commit(const std::string& sha) {
  if (sha.empty() || sha == "unknown" || sha.find("-dirty") != std::string::npos) return false;
  for (char c : sha)
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

bool code_changed_since(const std::string& sha, const std::string& id, const std::string& base) {
  if (!clean_commit(sha)) return true;
  std::string folder = shell_quote(fmt::format(":/experiments/{}", id));
  if (!base.empty()) folder += " " + shell_quote(fmt::format(":/experiments/{}", base));
  const std::string out = run_capture(fmt::format(
      "git diff --name-only {} -- ':/engine' ':/CMakeLists.txt' ':/cmake' {} 2>&1; echo \"rc=$?\"", sha,
      folder));
  const std::string untracked = run_capture(
      fmt::format("git status --porcelain --untracked-files=normal -- ':/engine' {} 2>/dev/null", folder));
  return out != "rc=0" || !untracked.empty();
}

int experiment_main(int argc, char** argv, const ExperimentBody& body) {
  std::string config_path, profile = "quick", out_path, slice_text, partial_path;
  std::vector<std::string> merge_paths;
  bool merge = false;
  unsigned threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto need = [&](const char* what) -> std::string {
      if (i + 1 >= argc) {
        fmt::print(stderr, "error: {} needs {}\n", a, what);
        usage(argv[0]);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--config") {
      config_path = need("a path");
    } else if (a == "--profile") {
      profile = need("a profile name");
    } else if (a == "--out") {
      out_path = need("a path");
    } else if (a == "--threads") {
      const std::string v = need("a number");
      char* end = nullptr;
      const long t = std::strtol(v.c_str(), &end, 10);
      if (*end != '\0' || t < 1 || t > 1024) {
        fmt::print(stderr, "error: --threads expects an integer in [1, 1024], got '{}'\n", v);
        return 2;
      }
      threads = static_cast<unsigned>(t);
    } else if (a == "--slice") {
      slice_text = need("k/N");
    } else if (a == "--partial") {
      partial_path = need("a path");
    } else if (a == "--merge") {
      merge = true;
      while (i + 1 < argc && std::string_view(argv[i + 1]).substr(0, 2) != "--")
        merge_paths.emplace_back(argv[++i]);
    } else if (a == "--help" || a == "-h") {
      usage(argv[0]);
      return 0;
    } else {
      fmt::print(stderr, "error: unknown argument '{}'\n", a);
      usage(argv[0]);
      return 2;
    }
  }
  if (config_path.empty()) {
    fmt::print(stderr, "error: --config is required\n");
    usage(argv[0]);
    return 2;
  }
  std::optional<Slice> slice;
  if (!slice_text.empty() || !partial_path.empty()) {
    if (slice_text.empty() || partial_path.empty() || merge) {
      fmt::print(stderr, "error: a shard run needs both --slice k/N and --partial FILE, and no --merge\n");
      return 2;
    }
    try {
      slice = Slice::parse(slice_text);
    } catch (const std::invalid_argument& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return 2;
    }
  }
  if (merge && merge_paths.empty()) {
    fmt::print(stderr, "error: --merge needs the partial files of every shard\n");
    return 2;
  }
  if (threads == 0) threads = default_threads();
  // The whole run, its serial parts too, on one BLAS thread: its numbers then do not depend on the machine's
  // cores (core/blas.hpp).
  const core::SingleThreadedBlas one_blas_thread;

  std::optional<Experiment> ex;
  try {
    ex.emplace(ExperimentConfig::load(config_path, profile), threads);
  } catch (const std::exception& e) {
    fmt::print(stderr, "config error: {}\n", e.what());
    return 2;
  }
  if (out_path.empty()) out_path = fmt::format("results/{}/latest.json", ex->id());
  const std::string sha = git_describe(std::filesystem::absolute(config_path).parent_path().string());

  const bool sharded = slice || merge;
  if (sharded && !ex->config().runs_whole.empty() && !(slice && slice->count == 1)) {
    fmt::print(stderr, "error: {} runs whole ({}): run it without --slice/--merge\n", ex->id(),
               ex->config().runs_whole);
    return 2;
  }
  std::size_t shards = 0;
  try {
    if (slice) {
      set_slice(*slice);
    } else if (merge) {
      std::vector<Partial> partials;
      for (const auto& f : merge_paths) partials.push_back(Partial::read(f));
      set_merge(std::move(partials));
      shards = merge_paths.size();
    } else {
      set_whole();
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
  // What identifies this run; a shard writes it into its partial, a merge requires it of every partial.
  PartialHeader run;
  run.id = ex->id();
  run.profile = profile;
  run.git_sha = sha;
  run.config_hash = ex->config().hash;
  run.seed = ex->seed();
  if (slice) run.slice = *slice;
  if (merge) {
    if (const auto d = header_difference(run, merged_header())) {
      fmt::print(stderr,
                 "error: cannot merge these partials into {} [{}]: they are of {} '{}', this run's is '{}'\n",
                 ex->id(), profile, d->what, d->b, d->a);
      return 2;
    }
  }

  const auto start = std::chrono::steady_clock::now();
  try {
    body(*ex);
    ex->params_done();
    check_merge_complete();
  } catch (const ConfigError& e) {
    fmt::print(stderr, "config error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    // A shard's own reduction runs on stand-in values for the other shards' trials and is discarded; if it
    // stops after the trial loops began, the partial keeps the loops run so far, and a merge that needs more
    // loops than a partial holds refuses it, naming the shard.
    if (slice && trial_loops_run() > 0) {
      fmt::print(stderr,
                 "{}: note: shard {}/{} stopped after {} trial loop(s) in its discarded reduction: {}\n",
                 ex->id(), slice->index, slice->count, trial_loops_run(), e.what());
    } else {
      fmt::print(stderr, "{}: run failed: {}\n", ex->id(), e.what());
      return 1;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (slice) {
    Partial p;
    p.header = run;
    p.loops = take_slice_records();
    if (p.loops.empty()) {
      fmt::print(stderr,
                 "error: {} ran no trial loop, so a shard would repeat the whole run; declare runs_whole = "
                 "\"<why>\" in {}\n",
                 ex->id(), config_path);
      return 2;
    }
    try {
      p.write(partial_path);
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: cannot write the partial file: {}\n", ex->id(), e.what());
      return 1;
    }
    std::size_t trials = 0, total = 0;
    for (const auto& l : p.loops) trials += l.end - l.begin, total += l.n;
    fmt::print(stderr, "{} [{}] shard {}/{}: {} of {} trials in {} trial loop(s) in {} -> {}\n", ex->id(),
               profile, slice->index, slice->count, trials, total, p.loops.size(), format_duration(wall),
               partial_path);
    return 0;
  }

  Results::Provenance prov;
  prov.id = ex->id();
  prov.profile = profile;
  prov.git_sha = sha;
  prov.shards = shards;
#if defined(__clang__)
  prov.compiler = fmt::format("clang {}", __clang_version__);
#elif defined(__GNUC__)
  prov.compiler = fmt::format("gcc {}", __VERSION__);
#else
  prov.compiler = "unknown";
#endif
  prov.config_file = config_path;
  prov.config_hash = ex->config().hash;
  prov.seed = ex->seed();
  prov.wall_time_s = wall;
  prov.threads = threads;
  prov.machine = this_machine();
  try {
    ex->results().write(out_path, prov);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: cannot write results: {}\n", ex->id(), e.what());
    return 1;
  }
  int failed = 0;
  for (const auto& c : ex->results().checks()) failed += c.passed ? 0 : 1;
  fmt::print(stderr, "{} [{}]: {} metrics, {} series, {} checks ({} not met) in {} -> {}\n", ex->id(),
             profile, ex->results().metrics().size(), ex->results().all_series().size(),
             ex->results().checks().size(), failed, format_duration(wall), out_path);
  return 0;
}

}  // namespace keel::repro
