// keel — the command-line front of the reproduction machinery (a thin consumer of keel.core):
//   keel list                                  experiment ids
//   keel diff   --profile P [ids...]           latest.json vs committed baseline.<P>.json under
//   experiment.toml tolerances keel bless  --profile P ids...             latest.json -> baseline.<P>.json
//   (numbers only), on purpose keel report --profile P [ids...]           paper/REPRODUCTION.md keel eta
//   --profile P ids...             baseline wall time per id (seconds), for progress estimates keel same
//   A.json B.json                  exit 0 when two result files agree except for provenance
// Options: --experiments DIR (experiments), --results DIR (results), --paper DIR (paper).
import keel.core;

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

struct Args {
  std::string command, profile = "full";
  std::filesystem::path experiments = "experiments", results = "results", paper = "paper";
  std::vector<std::string> ids;
};

int usage() {
  fmt::print(stderr,
             "usage: keel <list|diff|bless|report|eta|same> [--profile quick|full] [--experiments DIR] "
             "[--results DIR] [--paper DIR] [ids...]\n");
  return 2;
}

std::vector<std::string> resolve_ids(const Args& a) {
  auto all = keel::core::list_experiments(a.experiments);
  if (a.ids.empty()) return all;
  for (const auto& id : a.ids) {
    bool found = false;
    for (const auto& x : all) found = found || x == id;
    if (!found) {
      throw std::runtime_error(fmt::format("unknown experiment '{}' (known: {})", id, fmt::join(all, " ")));
    }
  }
  return a.ids;
}

keel::core::ExperimentConfig load(const Args& a, const std::string& id) {
  return keel::core::ExperimentConfig::load(a.experiments / id / "experiment.toml", a.profile);
}

// Reads provenance.wall_time_s from the baseline without a JSON library: the field is written by keel itself.
double baseline_wall(const Args& a, const std::string& id) {
  std::ifstream in(keel::core::baseline_path(a.results, id, a.profile));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find("\"wall_time_s\":");
  if (pos == std::string::npos) return -1;
  return std::strtod(text.c_str() + pos + 14, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (argc < 2) return usage();
  a.command = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(fmt::format("{} needs a value", s));
      return argv[++i];
    };
    try {
      if (s == "--profile")
        a.profile = next();
      else if (s == "--experiments")
        a.experiments = next();
      else if (s == "--results")
        a.results = next();
      else if (s == "--paper")
        a.paper = next();
      else if (s.rfind("--", 0) == 0) {
        fmt::print(stderr, "keel: unknown option '{}'\n", s);
        return usage();
      } else
        a.ids.push_back(s);
    } catch (const std::exception& e) {
      fmt::print(stderr, "keel: {}\n", e.what());
      return 2;
    }
  }
  try {
    if (a.command == "list") {
      for (const auto& id : keel::core::list_experiments(a.experiments)) fmt::print("{}\n", id);
      return 0;
    }
    if (a.command == "diff") {
      int failed = 0;
      for (const auto& id : resolve_ids(a)) {
        try {
          const auto d = keel::core::diff_against_baseline(load(a, id), a.results);
          fmt::print("{}\n", keel::core::format_diff(d));
          failed += d.ok() ? 0 : 1;
        } catch (const keel::core::ConfigError&) {
          throw;
        } catch (const std::exception& e) {
          fmt::print("{} [{}]: cannot compare: {}\n\n", id, a.profile, e.what());
          failed += 1;
        }
      }
      if (failed) fmt::print("{} experiment(s) left their baseline tolerance\n", failed);
      return failed ? 1 : 0;
    }
    if (a.command == "bless") {
      if (a.ids.empty())
        throw std::runtime_error("bless needs explicit experiment ids (baselines change only on purpose)");
      for (const auto& id : resolve_ids(a)) {
        keel::core::bless(load(a, id), a.results);
        fmt::print("blessed {}\n", keel::core::baseline_path(a.results, id, a.profile).string());
      }
      return 0;
    }
    if (a.command == "report") {
      keel::core::ReportOptions o;
      o.experiments_dir = a.experiments;
      o.results_dir = a.results;
      o.paper_dir = a.paper;
      o.profile = a.profile;
      o.ids = a.ids;
      fmt::print("wrote {}\n", keel::core::write_report(o).string());
      return 0;
    }
    if (a.command == "eta") {
      for (const auto& id : resolve_ids(a)) fmt::print("{} {:.3f}\n", id, baseline_wall(a, id));
      return 0;
    }
    if (a.command == "same") {
      if (a.ids.size() != 2) return usage();
      std::string why;
      if (keel::core::same_results(a.ids[0], a.ids[1], &why)) {
        fmt::print("identical (provenance aside)\n");
        return 0;
      }
      fmt::print("results differ: {}\n", why);
      return 1;
    }
  } catch (const keel::core::ConfigError& e) {
    fmt::print(stderr, "keel {}: config error: {}\n", a.command, e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keel {}: {}\n", a.command, e.what());
    return 1;
  }
  return usage();
}
