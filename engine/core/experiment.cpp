#include "core/experiment.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <optional>
#include <exception>
#include <filesystem>
#include <iostream>

#include "core/parallel.hpp"
#include "core/progress.hpp"

namespace keel::core {

Experiment::Experiment(ExperimentConfig config, unsigned threads)
    : config_(std::move(config)), threads_(threads) {}

namespace {

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

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void usage(const char* prog) {
  fmt::print(stderr,
             "usage: {} --config experiments/<id>/experiment.toml [--profile quick|full] "
             "[--out results/<id>/latest.json] [--threads N]\n",
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

bool code_changed_since(const std::string& sha, const std::string& id) {
  if (sha.empty() || sha == "unknown" || sha.find("-dirty") != std::string::npos) return true;
  for (char c : sha)
    if (!std::isxdigit(static_cast<unsigned char>(c))) return true;
  // experiments/common holds code that drivers include (shared glue), so it counts as the experiment's code
  // too.
  const std::string folder = shell_quote(fmt::format(":/experiments/{}", id));
  const std::string out = run_capture(fmt::format(
      "git diff --name-only {} -- ':/engine' ':/CMakeLists.txt' ':/cmake' ':/experiments/common' {} 2>&1; "
      "echo \"rc=$?\"",
      sha, folder));
  const std::string untracked = run_capture(fmt::format(
      "git status --porcelain --untracked-files=normal -- ':/engine' ':/experiments/common' {} 2>/dev/null",
      folder));
  return out != "rc=0" || !untracked.empty();
}

int experiment_main(int argc, char** argv, const ExperimentBody& body) {
  std::string config_path, profile = "quick", out_path;
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
  if (threads == 0) threads = default_threads();

  std::optional<Experiment> ex;
  try {
    ex.emplace(ExperimentConfig::load(config_path, profile), threads);
  } catch (const std::exception& e) {
    fmt::print(stderr, "config error: {}\n", e.what());
    return 2;
  }
  if (out_path.empty()) out_path = fmt::format("results/{}/latest.json", ex->id());

  const auto start = std::chrono::steady_clock::now();
  try {
    body(*ex);
    ex->params_done();
  } catch (const ConfigError& e) {
    fmt::print(stderr, "config error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: run failed: {}\n", ex->id(), e.what());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  Results::Provenance prov;
  prov.id = ex->id();
  prov.profile = profile;
  prov.git_sha = git_describe(std::filesystem::absolute(config_path).parent_path().string());
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

}  // namespace keel::core
