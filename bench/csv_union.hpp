// CSV output for keel's benchmarks whose header holds every user counter of the run. Google Benchmark's own
// CSVReporter takes its header from the first benchmark it reports and aborts ("All counters must be present
// in each run") when a later benchmark sets a counter the first did not; benchmarks of different solvers
// count different things. This reporter keeps every run and writes them at the end, one column per counter
// name seen anywhere (empty where a run has none). Used when --benchmark_format=csv is given
// (KEEL_BENCHMARK_MAIN).
#pragma once

#include <benchmark/benchmark.h>

#include <cstring>
#include <ostream>
#include <set>
#include <string>
#include <vector>

namespace keel::bench {

class CsvUnionReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    runs_.insert(runs_.end(), runs.begin(), runs.end());
  }
  void Finalize() override {
    std::set<std::string> names;
    for (const Run& r : runs_)
      for (const auto& [name, counter] : r.counters) names.insert(name);
    std::ostream& out = GetOutputStream();
    out << "name,iterations,real_time,cpu_time,time_unit,label,error_occurred,error_message";
    for (const std::string& n : names) out << ',' << quoted(n);
    out << '\n';
    for (const Run& r : runs_) {
      out << quoted(r.benchmark_name()) << ',' << r.iterations << ',' << r.GetAdjustedRealTime() << ','
          << r.GetAdjustedCPUTime() << ',' << benchmark::GetTimeUnitString(r.time_unit) << ','
          << quoted(r.report_label) << ',' << (r.error_occurred ? "true" : "false") << ','
          << quoted(r.error_message);
      for (const std::string& n : names) {
        out << ',';
        if (const auto it = r.counters.find(n); it != r.counters.end()) out << it->second.value;
      }
      out << '\n';
    }
  }

 private:
  static std::string quoted(const std::string& s) {
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + '"';
  }
  std::vector<Run> runs_;
};

// Runs the registered benchmarks as BENCHMARK_MAIN does, with CsvUnionReporter for --benchmark_format=csv.
inline int run_benchmarks(int argc, char** argv) {
  bool csv = false;
  for (int a = 1; a < argc; ++a) csv = csv || std::strcmp(argv[a], "--benchmark_format=csv") == 0;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (csv) {
    CsvUnionReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}

}  // namespace keel::bench

#define KEEL_BENCHMARK_MAIN() \
  int main(int argc, char** argv) { return keel::bench::run_benchmarks(argc, argv); }
