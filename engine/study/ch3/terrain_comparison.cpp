#include "study/ch3/terrain_comparison.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "core/statistics.hpp"
#include "datasets/manifest.hpp"
#include "repro/grading.hpp"
#include "study/ch3/config.hpp"
#include "study/ch3/shared.hpp"

namespace keel::study::ch3 {

using repro::Figure;
using repro::Layer;
using repro::Panel;
using repro::Results;
using repro::RunContext;

// ---------------------------------------------------------------------------------------------------------------
// Beyond Table 3.1: real terrain

TerrainComparison::Options TerrainComparison::Options::read(const core::ConfigTable& p) {
  Options o;
  o.table = AlignmentComparison::Options::read(p);
  o.dataset = p.string("dataset");
  o.grid_file = p.string("grid_file");
  o.roughness_bins = p.count("roughness_bins");
  o.length_unit = p.number("length_unit");
  o.block_size = p.number("block_size");
  if (!(o.block_size > 0 && std::isfinite(o.block_size)))
    throw core::ConfigError(fmt::format("{}: must be a length > 0 (m)", p.where("block_size")));
  if (!(o.length_unit > 0 && std::isfinite(o.length_unit)))
    throw core::ConfigError(fmt::format("{}: must be a length > 0 (m)", p.where("length_unit")));
  if (o.table.study.world.feature_dim != sim::TerrainField::kDim)
    throw core::ConfigError(fmt::format("{}: a terrain world has {} features (elevation, slope, curvature)",
                                        p.where("feature_dim"), sim::TerrainField::kDim));
  if (o.roughness_bins > o.table.study.worlds)
    throw core::ConfigError(fmt::format("{}: {} groups of {} worlds", p.where("roughness_bins"),
                                        o.roughness_bins, o.table.study.worlds));
  return o;
}

TerrainComparison::Outcome TerrainComparison::run(const Options& o, const RunContext& context) {
  Outcome out;
  out.options = o;
  const sim::TerrainField field(
      sim::read_terrain_grid(datasets::resolve_dataset_file(o.dataset, o.grid_file)));
  const sim::AlignmentWorldOptions& wo = o.table.study.world;
  const core::Streams& streams = context.streams();
  const auto world = [&](std::size_t w) {
    sim::TerrainWorld t = sim::make_terrain_world(field, wo, streams.seed(), streams.index(w));
    sim::to_length_units(t.world, o.length_unit);
    return WorldTruth{problem_of(t.world), t.world.theta, t.world.tx, t.world.ty};
  };
  core::Progress progress = context.progress(o.table.study.worlds);
  out.table.options = o.table;
  out.table.study = compare_methods(o.table.study.compare, o.table.study.worlds, context, world, &progress);
  progress.finish();
  // Where each world lies and how rough its terrain is (regenerated: cheap, and independent of sharding).
  for (std::size_t w = 0; w < o.table.study.worlds; ++w) {
    sim::TerrainWorld t = sim::make_terrain_world(field, wo, streams.seed(), streams.index(w));
    out.roughness.push_back(t.roughness), out.centre_x.push_back(t.centre_x),
        out.centre_y.push_back(t.centre_y);
    if (w == 0) out.world0 = std::move(t);
  }
  out.grid = field.grid();
  // Spatial blocks: square tiles of side block_size over the grid, by the reference's centre. Worlds of one
  // tile share most of their terrain, worlds of tiles that are not neighbours share none; the paired
  // comparisons take one value per tile (docs/GRADING.md "Paired orderings").
  std::vector<std::pair<long, long>> tiles;
  for (std::size_t w = 0; w < out.centre_x.size(); ++w) {
    const std::pair<long, long> t{
        static_cast<long>(std::floor((out.centre_x[w] - out.grid.x.front()) / o.block_size)),
        static_cast<long>(std::floor((out.centre_y[w] - out.grid.y.front()) / o.block_size))};
    auto it = std::find(tiles.begin(), tiles.end(), t);
    if (it == tiles.end()) it = tiles.insert(tiles.end(), t);
    out.table.blocks.push_back(static_cast<std::size_t>(it - tiles.begin()));
  }
  return out;
}

namespace {
// The roughness groups: the worlds split at the 1/k … (k−1)/k quantiles of their roughness; group g holds the
// worlds whose roughness lies in [edge g, edge g+1] (the last group closed), edges[0] = min, edges[k] = max.
std::vector<double> roughness_edges(const std::vector<double>& roughness, std::size_t k) {
  std::vector<double> edges;
  for (std::size_t g = 0; g <= k; ++g)
    edges.push_back(quantile(roughness, static_cast<double>(g) / static_cast<double>(k)));
  return edges;
}
std::size_t roughness_group(const std::vector<double>& edges, double r) {
  std::size_t g = 0;
  while (g + 2 < edges.size() && r >= edges[g + 1]) ++g;
  return g;
}
}  // namespace

void TerrainComparison::record(Results& r, const Outcome& out) {
  const Options& o = out.options;
  const AlignmentStudyOutcome& st = out.table.study;
  const std::vector<double> edges = roughness_edges(out.roughness, o.roughness_bins);
  // The family: Table 3.1's comparisons and, per roughness group, Proposed against SOConvHull (the thesis's
  // nearest competitor) in each error; all by spatial block.
  repro::PairedFamily family;
  add_table_comparisons(family, out.table);
  const auto pit = std::find(st.methods.begin(), st.methods.end(), Method::proposed);
  const auto sit = std::find(st.methods.begin(), st.methods.end(), Method::so_conv_hull);
  const bool by_roughness = pit != st.methods.end() && sit != st.methods.end();
  if (by_roughness) {
    const auto p = static_cast<std::size_t>(pit - st.methods.begin()),
               s = static_cast<std::size_t>(sit - st.methods.begin());
    for (std::size_t k = 0; k < o.roughness_bins; ++k) {
      std::vector<std::size_t> worlds;
      for (std::size_t w = 0; w < out.roughness.size(); ++w)
        if (roughness_group(edges, out.roughness[w]) == k) worlds.push_back(w);
      const repro::PairedOptions po = paired_options(subset(out.table.blocks, worlds));
      for (const bool rot : {true, false}) {
        std::vector<double> a, b;
        for (std::size_t w : worlds) {
          a.push_back(rot ? st.outcomes[p][w].rot_se : st.outcomes[p][w].trans_se);
          b.push_back(rot ? st.outcomes[s][w].rot_se : st.outcomes[s][w].trans_se);
        }
        family.add(repro::path(fmt::format("by_roughness{}", k)).under(rot ? "rot_se" : "trans_se").name(),
                   repro::paired_median(a, b, po));
      }
    }
  }
  family.adjust();
  record_table(r, out.table, family);
  std::vector<std::size_t> distinct = out.table.blocks;
  std::sort(distinct.begin(), distinct.end());
  r.metric("blocks", static_cast<double>(std::unique(distinct.begin(), distinct.end()) - distinct.begin()));
  r.metric("block_size", o.block_size);
  const sim::TerrainGrid& g = out.grid;
  r.metric("grid.rows", static_cast<double>(g.rows()));
  r.metric("grid.cols", static_cast<double>(g.cols()));
  r.metric("grid.extent_x", g.x.back() - g.x.front());
  r.metric("grid.extent_y", g.y.back() - g.y.front());
  r.metric("grid.spacing_x", (g.x.back() - g.x.front()) / static_cast<double>(g.cols() - 1));
  r.metric("grid.spacing_y", (g.y.back() - g.y.front()) / static_cast<double>(g.rows() - 1));
  const auto [zmin, zmax] = std::minmax_element(g.z.begin(), g.z.end());
  r.metric("grid.z_min", *zmin);
  r.metric("grid.z_max", *zmax);
  r.metric("roughness.median", median_of(out.roughness));
  r.series("roughness.edges", edges);
  for (std::size_t m = 0; m < st.methods.size(); ++m) {
    const std::string name(align::to_string(st.methods[m]));
    // Per roughness group: median errors (translation SE in length units²) and valid rate.
    std::vector<std::vector<double>> rot(o.roughness_bins), trans(o.roughness_bins);
    std::vector<double> valid(o.roughness_bins, 0.0), count(o.roughness_bins, 0.0);
    for (std::size_t w = 0; w < st.outcomes[m].size(); ++w) {
      const std::size_t k = roughness_group(edges, out.roughness[w]);
      rot[k].push_back(st.outcomes[m][w].rot_se), trans[k].push_back(st.outcomes[m][w].trans_se);
      valid[k] += st.outcomes[m][w].valid, count[k] += 1;
    }
    std::vector<double> rot_med, trans_med, valid_rate;
    for (std::size_t k = 0; k < o.roughness_bins; ++k) {
      rot_med.push_back(rot[k].empty() ? 0.0 : median_of(rot[k]));
      trans_med.push_back(trans[k].empty() ? 0.0 : median_of(trans[k]));
      valid_rate.push_back(count[k] > 0 ? 100.0 * valid[k] / count[k] : 0.0);
    }
    r.under(name).series("by_roughness.rot_se.median", rot_med);
    r.under(name).series("by_roughness.trans_se.median", trans_med);
    r.under(name).series("by_roughness.valid_rate", valid_rate);
    // Rank correlation of the errors with the roughness (Spearman: Pearson on ranks, ties at their mean
    // rank).
    std::vector<double> rots, transes;
    for (const auto& w : st.outcomes[m]) rots.push_back(w.rot_se), transes.push_back(w.trans_se);
    r.under(name).metric("spearman.rot_se_roughness", core::spearman(out.roughness, rots));
    r.under(name).metric("spearman.trans_se_roughness", core::spearman(out.roughness, transes));
  }
  // Paired by roughness group: Proposed minus SOConvHull, from the family.
  if (by_roughness) {
    std::map<std::string, std::vector<double>> series;
    for (std::size_t k = 0; k < o.roughness_bins; ++k)
      for (const char* label : {"rot_se", "trans_se"}) {
        const repro::PairedComparison& c =
            family.at(repro::path(fmt::format("by_roughness{}", k)).under(label).name());
        const auto key = repro::path("paired").under("by_roughness").under(label).under("so_conv_hull");
        series[key.key("difference")].push_back(c.difference);
        series[key.key("low")].push_back(c.low);
        series[key.key("high")].push_back(c.high);
        series[key.key("adjusted_p")].push_back(c.adjusted_p);
      }
    for (auto& [key, v] : series) r.series(key, std::move(v));
  }
}

std::vector<Figure> TerrainComparison::figures(const Outcome& out) {
  std::vector<Figure> figures = AlignmentComparison::figures(out.table);
  const Options& o = out.options;
  const sim::TerrainGrid& g = out.grid;
  const AlignmentStudyOutcome& st = out.table.study;
  Figure f;
  f.file = "_terrain.png";
  f.title = fmt::format(
      "Real terrain ({}): the grid and world 0's surveys; errors against the roughness under the "
      "query, {} worlds",
      o.dataset + "/" + o.grid_file, o.table.study.worlds);
  Panel map, pr, pt;
  map.title =
      "(a) elevation (km offsets from the grid's centre), world 0's reference (white) and query (black)";
  map.xlabel = "x (km)", map.ylabel = "y (km)", map.aspect = "equal", map.colorbar = "elevation (m)";
  // At most ~150 × 150 squares: every k-th node.
  const std::size_t k = std::max<std::size_t>(1, std::max(g.rows(), g.cols()) / 150);
  std::vector<double> gx, gy, gz;
  for (std::size_t i = 0; i < g.rows(); i += k)
    for (std::size_t c = 0; c < g.cols(); c += k)
      gx.push_back(g.x[c] / 1000), gy.push_back(g.y[i] / 1000), gz.push_back(g.at(i, c));
  const auto [zmin, zmax] = std::minmax_element(g.z.begin(), g.z.end());
  const double cells = static_cast<double>(std::max(g.rows(), g.cols()) / k);
  Layer grid =
      repro::scatter_layer(std::move(gx), std::move(gy), "", "k", std::pow(330.0 / cells, 2), 1.0, "s");
  grid.c = std::move(gz), grid.cmap = "terrain", grid.vmin = *zmin, grid.vmax = *zmax;
  map.layers.push_back(std::move(grid));
  const sim::AlignmentWorld& w0 = out.world0.world;
  const auto km = [](const std::vector<double>& v, double shift) {
    std::vector<double> s;
    for (double e : v) s.push_back((e + shift) / 1000);
    return s;
  };
  map.layers.push_back(repro::line_layer(km(w0.ref_x, out.world0.centre_x), km(w0.ref_y, out.world0.centre_y),
                                         "reference (world 0)", "white"));
  map.layers.back().linewidth = 0.5;
  map.layers.push_back(repro::line_layer(km(w0.query_true_x, out.world0.centre_x),
                                         km(w0.query_true_y, out.world0.centre_y),
                                         "query (world 0, true place)", "k"));
  map.layers.back().linewidth = 0.6;
  map.legend = "upper right";
  pr.title = "(b) rotation SE against the roughness under the query";
  pt.title = "(c) translation SE against the roughness under the query";
  pr.xlabel = pt.xlabel = "elevation RMS about its plane over the query (m)";
  pr.ylabel = "rad²", pt.ylabel = fmt::format("({:g} m length units)²", o.length_unit);
  pr.xscale = pt.xscale = pr.yscale = pt.yscale = "log";
  pt.legend = "none";
  const char* markers[] = {"o", "s", "^", "v"};
  for (std::size_t m = 0; m < st.methods.size(); ++m) {
    std::vector<double> rot, trans;
    for (const auto& w : st.outcomes[m])
      rot.push_back(std::max(w.rot_se, 1e-12)), trans.push_back(std::max(w.trans_se, 1e-12));
    const std::string name(align::to_string(st.methods[m]));
    pr.layers.push_back(
        repro::scatter_layer(out.roughness, rot, name, kColors[m % 4], 10, 0.6, markers[m % 4]));
    pt.layers.push_back(
        repro::scatter_layer(out.roughness, trans, name, kColors[m % 4], 10, 0.6, markers[m % 4]));
  }
  f.panels = {map, pr, pt};
  f.cols = 3, f.rows = 1, f.width = 18.0, f.height = 5.6;
  figures.push_back(f);
  return figures;
}

}  // namespace keel::study::ch3
