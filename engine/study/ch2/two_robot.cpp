#include "study/ch2/two_robot.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>

#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "repro/results.hpp"
#include "graph/residuals.hpp"
#include "pcm/consistency.hpp"

namespace keel::study::ch2 {

std::vector<MergeMethod> methods_of(const std::vector<StudyMethod>& methods) {
  std::vector<MergeMethod> out;
  out.reserve(methods.size());
  for (const auto& m : methods) out.push_back(m.method);
  return out;
}

std::size_t method_index(const std::vector<StudyMethod>& methods, std::string_view name,
                         std::string_view who) {
  for (std::size_t k = 0; k < methods.size(); ++k)
    if (methods[k].method.name == name) return k;
  throw std::invalid_argument(fmt::format("{} names method '{}', not in `methods`", who, name));
}

void MeasurementRegime::validate() const {
  if (!(std::isfinite(noise_scale) && noise_scale > 0.0))
    throw std::invalid_argument(fmt::format(
        "MeasurementRegime '{}': noise_scale must be finite and > 0 (got {:g})", name, noise_scale));
  if (!resampled && noise_scale != 1.0)
    throw std::invalid_argument(
        fmt::format("MeasurementRegime '{}': the dataset's own measurements have noise_scale 1 (got {:g})",
                    name, noise_scale));
}

template <class G>
sim::TwoRobotScenario<G> apply_regime(const sim::TwoRobotScenario<G>& base, const MeasurementRegime& regime) {
  regime.validate();
  auto scenario = base;
  if (regime.resampled) sim::resample_measurements(scenario, regime.noise_scale, regime.resample_seed);
  return scenario;
}

sim::CandidateOptions apply_regime(const sim::CandidateOptions& candidates, const MeasurementRegime& regime) {
  regime.validate();
  auto c = candidates;
  c.aliased_noise_scale = regime.noise_scale;
  return c;
}

template <class G>
LocalPair<G> solve_local_pair(const sim::TwoRobotScenario<G>& scenario, const LocalSolveOptions& options) {
  return {solve_local(scenario.robot_a, options), solve_local(scenario.robot_b, options)};
}

template <class G>
void record_local_pair(repro::Results& r, const sim::TwoRobotScenario<G>& scenario,
                       const LocalPair<G>& local) {
  r.timing("local.a.solve", local.a.solve_time_s);
  r.timing("local.b.solve", local.b.solve_time_s);
  r.timing("local.a.factorization", local.a.factorization_time_s);
  r.timing("local.b.factorization", local.b.factorization_time_s);
  int closures_a = 0, closures_b = 0;
  for (const auto& e : scenario.robot_a.edges) closures_a += std::abs(e.i - e.j) != 1;
  for (const auto& e : scenario.robot_b.edges) closures_b += std::abs(e.i - e.j) != 1;
  r.metric("scenario.pool", static_cast<double>(scenario.pool.size()));
  r.metric("scenario.robot_a.poses", static_cast<double>(scenario.truth_a.size()));
  r.metric("scenario.robot_b.poses", static_cast<double>(scenario.truth_b.size()));
  r.metric("scenario.robot_a.loop_closures", closures_a);
  r.metric("scenario.robot_b.loop_closures", closures_b);
  r.metric("local.a.normalized_chi2", local.a.summary.normalized_chi2);
  r.metric("local.b.normalized_chi2", local.b.summary.normalized_chi2);
}

template <class G>
std::vector<MergeDataset<G>> run_merge_datasets(const sim::TwoRobotScenario<G>& scenario,
                                                const LocalPair<G>& local,
                                                const sim::CandidateOptions& candidates,
                                                const std::vector<MergeMethod>& methods,
                                                const repro::RunContext& context, std::size_t count,
                                                std::size_t keep, core::Progress* progress) {
  std::vector<MergeDataset<G>> runs(count);
  context.trials(  // one trial per data set; its record is the MergeDataset
      count,
      [&](std::size_t i) {
        runs[i] = run_merge_dataset(scenario, local.a, local.b, candidates, methods, context.streams().seed(),
                                    context.streams().index(i), i == keep);
      },
      progress, runs);
  return runs;
}

template <class G>
std::vector<MergeDataset<G>> run_method_sweep(const sim::TwoRobotScenario<G>& scenario,
                                              const LocalPair<G>& local,
                                              const sim::CandidateOptions& candidates,
                                              const std::vector<std::vector<MergeMethod>>& method_sets,
                                              const repro::RunContext& context, std::size_t index,
                                              core::Progress* progress) {
  std::vector<MergeDataset<G>> sweep(method_sets.size());
  context.trials(  // one trial per method set, all on data set `index`
      method_sets.size(),
      [&](std::size_t k) {
        sweep[k] = run_merge_dataset(scenario, local.a, local.b, candidates, method_sets[k],
                                     context.streams().seed(), context.streams().index(index));
      },
      progress, sweep);
  return sweep;
}

template <class G>
std::vector<pcm::ConsistencyMatrix> dataset_consistency_matrices(const sim::TwoRobotScenario<G>& scenario,
                                                                 const LocalPair<G>& local,
                                                                 const sim::CandidateOptions& candidates,
                                                                 std::uint64_t seed, std::size_t count,
                                                                 std::uint64_t index_base) {
  std::vector<pcm::ConsistencyMatrix> out;
  out.reserve(count);
  pcm::ConsistencyOptions co;
  co.threads = 1;
  co.composition = pcm::Composition::joint;
  for (std::size_t i = 0; i < count; ++i) {
    const auto set = sim::generate_candidates(scenario, candidates, seed, index_base + i);
    const auto maps = merge::local_maps(local.a, local.b, set.candidates);
    out.push_back(pcm::consistency_matrix(maps.a, maps.b, set.candidates, co));
  }
  return out;
}

const std::vector<double>& MethodSummary::column(std::string_view name) const {
  const auto it = columns.find(name);
  if (it != columns.end()) return it->second;
  std::string valid;
  for (const auto& [key, v] : columns) valid += (valid.empty() ? "" : ", ") + key;
  throw std::invalid_argument(fmt::format("MethodSummary: no column '{}' (valid: {})", name, valid));
}

template <class G>
MethodSummary summarize_method(const std::vector<MergeDataset<G>>& runs, std::size_t k) {
  MethodSummary s;
  auto& c = s.columns;
  for (const auto& d : runs) {
    const auto& o = d.methods.at(k);
    const auto& m = o.metrics;
    for (int u : o.selection.selected) {
      const auto kind = d.candidates.labels[static_cast<std::size_t>(u)].kind;
      s.accepted_aliased += kind == sim::MeasurementLabel::aliased;
      s.accepted_random += kind == sim::MeasurementLabel::random;
    }
    s.empty_selections += o.selection.selected.empty();
    c["trans_mse"].push_back(m.map.translation_mse);
    c["rot_mse"].push_back(m.map.rotation);
    c["rel_pose_trans_mse"].push_back(m.anchor_translation_sq);
    c["rel_pose_rot"].push_back(m.anchor_rotation);
    c["traj_trans_mse"].push_back(m.trajectory.translation_mse);
    c["traj_rot"].push_back(m.trajectory.rotation);
    c["residual"].push_back(m.residual);
    c["chi2"].push_back(m.normalized_chi2);
    c["selected"].push_back(static_cast<double>(o.selection.selected.size()));
    c["tp"].push_back(static_cast<double>(m.classification.tp));
    c["fp"].push_back(static_cast<double>(m.classification.fp));
    c["raw_size"].push_back(static_cast<double>(o.selection.raw_size));
    c["violations"].push_back(static_cast<double>(o.selection.violations));
    c["selection_time_s"].push_back(o.selection.time_s);
    c["solve_time_s"].push_back(o.solve_time_s);
    s.pooled.tp += m.classification.tp;
    s.pooled.fp += m.classification.fp;
    s.pooled.fn += m.classification.fn;
    s.pooled.tn += m.classification.tn;
  }
  return s;
}

template <class G>
void record_dataset_timings(repro::Results& r, const std::vector<MergeDataset<G>>& runs) {
  std::vector<double> t_cov, t_q, t_qi;
  for (const auto& d : runs) {
    t_cov.push_back(d.covariance_time_s);
    t_q.push_back(d.matrix_time_s);
    t_qi.push_back(d.matrix_independent_time_s);
  }
  for (const auto& [name, v] : {std::pair<const char*, const std::vector<double>*>{"cov_extraction", &t_cov},
                                {"matrix", &t_q},
                                {"matrix_independent", &t_qi}}) {
    const auto s = core::mean_std(*v);
    const auto at = r.under("dataset").under(name);
    at.timing("mean", s.mean);
    at.timing("max", s.max);
  }
}

template <class G>
std::size_t same_selections(const std::vector<MergeDataset<G>>& runs, std::size_t i, std::size_t j) {
  std::size_t same = 0;
  for (const auto& d : runs) same += d.methods.at(i).selection.selected == d.methods.at(j).selection.selected;
  return same;
}

template <class G>
std::size_t proven_optimal(const std::vector<MergeDataset<G>>& runs, std::size_t i) {
  std::size_t proven = 0;
  for (const auto& d : runs) proven += d.methods.at(i).selection.proven_optimal();
  return proven;
}

template <class G>
double pool_chi2_at_truth(const sim::TwoRobotScenario<G>& s) {
  if (s.pool.empty()) throw std::invalid_argument("pool_chi2_at_truth: the scenario's pool is empty");
  double sum = 0.0;
  for (std::size_t u = 0; u < s.pool.size(); ++u) {
    const auto& c = s.pool[u];
    const G X = s.truth_a[static_cast<std::size_t>(c.pose_a)].inverse() * s.true_anchor *
                s.truth_b[static_cast<std::size_t>(c.pose_b)];
    const auto r = graph::edge_residual(c.z, G(), X);  // ρ(z⁻¹ X), the convention of pose_graph.hpp
    sum += r.dot(s.pool_information[u] * r) / static_cast<double>(G::DoF);
  }
  return sum / static_cast<double>(s.pool.size());
}

PoolCalibration pool_calibration(const LocalPair<lie::SE2>& local, const sim::TwoRobotScenario2& scenario,
                                 pcm::Composition composition, const std::vector<double>& gammas) {
  const auto maps = local_maps(local.a, local.b, scenario.pool);
  pcm::ConsistencyOptions co;
  co.composition = composition;
  co.threads = 1;
  const auto Q = pcm::consistency_matrix(maps.a, maps.b, scenario.pool, co);
  if (Q.n < 2) throw std::invalid_argument("pool_calibration: the pool needs at least two loop closures");
  PoolCalibration out;
  out.fail.assign(gammas.size(), 0.0);
  double sum = 0.0, pairs = 0.0;
  for (int u = 0; u < Q.n; ++u)
    for (int v = 0; v < Q.n; ++v) {
      if (u == v) continue;
      const double q = Q.at(u, v);
      sum += q;
      pairs += 1.0;
      for (std::size_t j = 0; j < gammas.size(); ++j) out.fail[j] += q > gammas[j];
    }
  for (auto& f : out.fail) f /= pairs;
  out.q_mean = sum / pairs;
  return out;
}

// Explicit instantiations: planar (SE(2)) and 3D (SE(3)) scenarios.
#define KEEL_EVAL_STUDIES(G)                                                                                 \
  template sim::TwoRobotScenario<G> apply_regime(const sim::TwoRobotScenario<G>&, const MeasurementRegime&); \
  template LocalPair<G> solve_local_pair(const sim::TwoRobotScenario<G>&, const LocalSolveOptions&);         \
  template void record_local_pair(repro::Results&, const sim::TwoRobotScenario<G>&, const LocalPair<G>&);    \
  template std::vector<MergeDataset<G>> run_merge_datasets(                                                  \
      const sim::TwoRobotScenario<G>&, const LocalPair<G>&, const sim::CandidateOptions&,                    \
      const std::vector<MergeMethod>&, const repro::RunContext&, std::size_t, std::size_t, core::Progress*); \
  template std::vector<MergeDataset<G>> run_method_sweep(                                                    \
      const sim::TwoRobotScenario<G>&, const LocalPair<G>&, const sim::CandidateOptions&,                    \
      const std::vector<std::vector<MergeMethod>>&, const repro::RunContext&, std::size_t, core::Progress*); \
  template MethodSummary summarize_method(const std::vector<MergeDataset<G>>&, std::size_t);                 \
  template void record_dataset_timings(repro::Results&, const std::vector<MergeDataset<G>>&);                \
  template std::size_t same_selections(const std::vector<MergeDataset<G>>&, std::size_t, std::size_t);       \
  template std::size_t proven_optimal(const std::vector<MergeDataset<G>>&, std::size_t);                     \
  template double pool_chi2_at_truth(const sim::TwoRobotScenario<G>&);                                       \
  template std::vector<pcm::ConsistencyMatrix> dataset_consistency_matrices(                                 \
      const sim::TwoRobotScenario<G>&, const LocalPair<G>&, const sim::CandidateOptions&, std::uint64_t,     \
      std::size_t, std::uint64_t);
KEEL_EVAL_STUDIES(lie::SE2)
KEEL_EVAL_STUDIES(lie::SE3)
#undef KEEL_EVAL_STUDIES

}  // namespace keel::study::ch2
