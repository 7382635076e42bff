// The reproduction commands of `keel` (thin consumers of keel.core):
//   keel list                          experiment ids
//   keel diff   --profile P [ids...]   latest.json vs committed baseline.<P>.json under experiment.toml
//   tolerances keel bless  --profile P ids...     latest.json -> baseline.<P>.json (numbers only), on purpose
//   keel report --profile P [ids...]   paper/REPRODUCTION.md
//   keel eta    --profile P [ids...]   baseline wall time per id (seconds), for progress estimates
//   keel same   A.json B.json          exit 0 when two result files agree except for provenance
import keel.core;
import keel.repro;

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"

namespace keel::cli {

namespace {

struct ReproArgs {
  std::string profile = "full";
  std::string from = "latest";  // report: latest.json or the committed baselines
  std::string experiments = "experiments", results = "results", paper = "paper";
  std::vector<std::string> ids;
};

std::vector<std::string> resolve_ids(const ReproArgs& a) {
  auto all = keel::repro::list_experiments(a.experiments);
  if (a.ids.empty()) return all;
  for (const auto& id : a.ids) {
    bool found = false;
    for (const auto& x : all) found = found || x == id;
    if (!found) {
      throw std::invalid_argument(
          fmt::format("unknown experiment '{}' (known: {})", id, fmt::join(all, " ")));
    }
  }
  return a.ids;
}

keel::repro::ExperimentConfig load(const ReproArgs& a, const std::string& id) {
  return keel::repro::ExperimentConfig::load(std::filesystem::path(a.experiments) / id / "experiment.toml",
                                             a.profile);
}

// Reads provenance.wall_time_s from the baseline without a JSON library: the field is written by keel itself.
double baseline_wall(const ReproArgs& a, const std::string& id) {
  std::ifstream in(keel::repro::baseline_path(a.results, id, a.profile));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto pos = text.find("\"wall_time_s\":");
  if (pos == std::string::npos) return -1;
  return std::strtod(text.c_str() + pos + 14, nullptr);
}

CLI::App* repro_command(CLI::App& app, const char* name, const char* help, ReproArgs& a, bool ids) {
  auto* c = app.add_subcommand(name, help);
  c->group("Reproduction");
  c->add_option("--profile", a.profile, "quick or full")->capture_default_str();
  c->add_option("--experiments", a.experiments, "experiment folders")->capture_default_str();
  c->add_option("--results", a.results, "results folder")->capture_default_str();
  if (ids) c->add_option("ids", a.ids, "experiment ids (default: all)");
  return c;
}

}  // namespace

void add_repro_commands(CLI::App& app) {
  auto a = std::make_shared<ReproArgs>();
  repro_command(app, "list", "list the experiment ids", *a, false)->callback([a] {
    for (const auto& id : keel::repro::list_experiments(a->experiments)) fmt::print("{}\n", id);
  });
  repro_command(app, "diff", "compare results/<id>/latest.json with its committed baseline", *a, true)
      ->callback([a] {
        int failed_count = 0;
        for (const auto& id : resolve_ids(*a)) {
          try {
            const auto d = keel::repro::diff_against_baseline(load(*a, id), a->results);
            fmt::print("{}\n", keel::repro::format_diff(d));
            failed_count += d.ok() ? 0 : 1;
          } catch (const keel::core::ConfigError&) {
            throw;
          } catch (const std::exception& e) {
            fmt::print("{} [{}]: cannot compare: {}\n\n", id, a->profile, e.what());
            failed_count += 1;
          }
        }
        if (failed_count) {
          throw CommandFailed(fmt::format("{} experiment(s) left their baseline tolerance", failed_count));
        }
      });
  repro_command(app, "bless", "write latest.json as the baseline (numbers only; on purpose)", *a, true)
      ->callback([a] {
        if (a->ids.empty()) {
          throw CLI::ValidationError(
              "ids", "bless needs explicit experiment ids (baselines change only on purpose)");
        }
        for (const auto& id : resolve_ids(*a)) {
          keel::repro::bless(load(*a, id), a->results);
          fmt::print("blessed {}\n", keel::repro::baseline_path(a->results, id, a->profile).string());
        }
      });
  auto* report = repro_command(app, "report", "render paper/REPRODUCTION.md from the results", *a, true);
  report->add_option("--paper", a->paper, "output folder")->capture_default_str();
  report
      ->add_option("--from", a->from,
                   "latest: this machine's last runs (results/<id>/latest.json); baseline: the committed "
                   "baselines (results/<id>/baseline.<profile>.json), the report a clone regenerates")
      ->check(CLI::IsMember({"latest", "baseline"}))
      ->capture_default_str();
  app.get_subcommand("report")->callback([a] {
    keel::repro::ReportOptions o;
    o.experiments_dir = a->experiments;
    o.results_dir = a->results;
    o.paper_dir = a->paper;
    o.profile = a->profile;
    o.ids = a->ids;
    o.from_baseline = a->from == "baseline";
    fmt::print("wrote {}\n", keel::repro::write_report(o).string());
  });
  repro_command(app, "eta", "baseline wall time per experiment (seconds)", *a, true)->callback([a] {
    for (const auto& id : resolve_ids(*a)) fmt::print("{} {:.3f}\n", id, baseline_wall(*a, id));
  });
  auto* prose = app.add_subcommand(
      "prose-check", "fail on numbers typed by hand in the discussions (thesis numbers and settings aside)");
  prose->group("Reproduction");
  auto prose_ids = std::make_shared<std::vector<std::string>>();
  prose->add_option("ids", *prose_ids, "experiments (default: all)");
  prose->callback([prose_ids] {
    const auto ids = prose_ids->empty() ? keel::repro::list_experiments("experiments") : *prose_ids;
    std::size_t count = 0;
    for (const auto& id : ids) {
      const auto cfg =
          keel::repro::ExperimentConfig::load(fmt::format("experiments/{}/experiment.toml", id), "full");
      for (const auto& p : keel::repro::prose_number_problems(cfg)) fmt::print("{}\n", p), ++count;
    }
    if (count > 0) throw CommandFailed(fmt::format("{} number(s) typed by hand in the discussions", count));
    fmt::print("no number typed by hand in {} discussion(s)\n", ids.size());
  });
  auto* same = app.add_subcommand("same", "exit 0 when two result files agree except for provenance");
  same->group("Reproduction");
  auto files = std::make_shared<std::vector<std::string>>();
  same->add_option("files", *files, "two result files")->required()->expected(2);
  same->callback([files] {
    std::string why;
    if (keel::repro::same_results((*files)[0], (*files)[1], &why)) {
      fmt::print("identical (provenance aside)\n");
      return;
    }
    fmt::print("results differ: {}\n", why);
    throw CommandFailed("the result files differ");
  });
}

}  // namespace keel::cli
