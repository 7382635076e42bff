// keel report --profile P [ids...] — paper/REPRODUCTION.md from this machine's runs or the committed
// baselines.
import keel.core;
import keel.repro;
import keel.app;

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "repro_common.hpp"

namespace keel::cli {

namespace {

struct ReportArgs : ReproArgs {
  std::string from = "latest";  // latest.json or the committed baselines
  std::string paper = "paper";
};

}  // namespace

void add_report_command(CLI::App& app) {
  auto a = std::make_shared<ReportArgs>();
  auto* report = repro_command(app, "report", "render paper/REPRODUCTION.md from the results", *a, true);
  report->add_option("--paper", a->paper, "output folder")->capture_default_str();
  report
      ->add_option("--from", a->from,
                   "latest: this machine's last runs (results/<id>/latest.json); baseline: the committed "
                   "baselines (results/<id>/baseline.<profile>.json), the report a clone regenerates")
      ->check(CLI::IsMember({"latest", "baseline"}))
      ->capture_default_str();
  report->callback([a] {
    resolve_ids(*a);  // a missing experiments folder or an unknown id: bad input, before anything is read
    app::check_folder_writable("--paper", a->paper);
    repro::ReportOptions o;
    o.experiments_dir = a->experiments;
    o.results_dir = a->results;
    o.paper_dir = a->paper;
    o.profile = a->profile;
    o.ids = a->ids;
    o.from_baseline = a->from == "baseline";
    fmt::print("wrote {}\n", repro::write_report(o).string());
  });
}

}  // namespace keel::cli
