#include "repro/results.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace keel::repro {

using json = nlohmann::json;

double round_significant(double v, int digits) {
  if (!std::isfinite(v) || v == 0.0) return v;
  return std::strtod(fmt::format("{:.{}g}", v, digits).c_str(), nullptr);
}

Layer line_layer(std::vector<double> x, std::vector<double> y, std::string label, std::string color,
                 std::string marker, std::string linestyle) {
  Layer l;
  l.type = "line";
  l.x = std::move(x);
  l.y = std::move(y);
  l.label = std::move(label);
  l.color = std::move(color);
  l.marker = std::move(marker);
  l.linestyle = std::move(linestyle);
  return l;
}

Layer scatter_layer(std::vector<double> x, std::vector<double> y, std::string label, std::string color,
                    double size, double alpha, std::string marker) {
  Layer l;
  l.type = "scatter";
  l.x = std::move(x);
  l.y = std::move(y);
  l.label = std::move(label);
  l.color = std::move(color);
  l.size = size;
  if (alpha < 1.0) l.alpha = alpha;
  l.marker = std::move(marker);
  return l;
}

Layer histogram_layer(const std::vector<double>& bins, const std::vector<double>& freq, std::string label,
                      std::string color) {
  if (freq.size() != bins.size())
    throw std::invalid_argument(
        fmt::format("histogram_layer: {} frequencies for {} bins", freq.size(), bins.size()));
  std::vector<double> x, y;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    x.insert(x.end(), {bins[b] - 0.5, bins[b] - 0.5, bins[b] + 0.5, bins[b] + 0.5});
    y.insert(y.end(), {0.0, freq[b], freq[b], 0.0});
  }
  return line_layer(std::move(x), std::move(y), std::move(label), std::move(color));
}

Layer ecdf_layer(std::vector<double> values, std::string label, std::string color, double floor,
                 std::string linestyle) {
  std::sort(values.begin(), values.end());
  std::vector<double> frac(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    frac[k] = static_cast<double>(k + 1) / static_cast<double>(values.size());
    values[k] = std::max(values[k], floor);
  }
  return line_layer(std::move(values), std::move(frac), std::move(label), std::move(color), "",
                    std::move(linestyle));
}

Layer hline_layer(double y, std::string label, std::string color, std::string linestyle) {
  Layer l;
  l.type = "hline";
  l.value = y;
  l.label = std::move(label);
  l.color = std::move(color);
  l.linestyle = std::move(linestyle);
  return l;
}

std::string level_tag(double p) {
  if (!(p > 0 && p < 1)) throw std::invalid_argument("level_tag: level must lie in (0, 1)");
  std::string s = fmt::format("{:.6f}", p).substr(2);  // digits after "0."
  while (!s.empty() && s.back() == '0') s.pop_back();
  return s;
}

namespace {

json number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return round_significant(v);
}

json numbers(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(number(x));
  return a;
}

json layer_json(const Layer& l) {
  json j;
  j["type"] = l.type;
  auto arr = [&](const char* k, const std::vector<double>& v) {
    if (!v.empty()) j[k] = numbers(v);
  };
  auto str = [&](const char* k, const std::string& s) {
    if (!s.empty()) j[k] = s;
  };
  auto opt = [&](const char* k, const std::optional<double>& v) {
    if (v) j[k] = number(*v);
  };
  if (l.type == "line" || l.type == "scatter") {
    j["x"] = numbers(l.x);
    if (l.y_timings.empty()) {
      j["y"] = numbers(l.y);
    } else {
      j["y_timings"] = l.y_timings;
    }
  }
  arr("x0", l.x0);
  arr("y0", l.y0);
  arr("x1", l.x1);
  arr("y1", l.y1);
  arr("c", l.c);
  if (l.value) j[l.type == "vline" ? "x" : "y"] = number(*l.value);
  str("label", l.label);
  str("color", l.color);
  str("marker", l.marker);
  str("linestyle", l.linestyle);
  str("cmap", l.cmap);
  opt("size", l.size);
  opt("alpha", l.alpha);
  opt("linewidth", l.linewidth);
  opt("vmin", l.vmin);
  opt("vmax", l.vmax);
  return j;
}

json figure_json(const Figure& f) {
  json j;
  j["file"] = f.file;
  if (!f.title.empty()) j["title"] = f.title;
  if (f.rows > 0 && f.cols > 0) j["layout"] = {f.rows, f.cols};
  if (f.width > 0 && f.height > 0) j["size"] = {f.width, f.height};
  json panels = json::array();
  for (const auto& p : f.panels) {
    json pj;
    auto str = [&](const char* k, const std::string& s) {
      if (!s.empty()) pj[k] = s;
    };
    str("title", p.title);
    str("xlabel", p.xlabel);
    str("ylabel", p.ylabel);
    str("xscale", p.xscale);
    str("yscale", p.yscale);
    str("aspect", p.aspect);
    str("legend", p.legend);
    str("colorbar", p.colorbar);
    if (p.xlim) pj["xlim"] = {p.xlim->first, p.xlim->second};
    if (p.ylim) pj["ylim"] = {p.ylim->first, p.ylim->second};
    if (!p.xticks.empty()) pj["xticks"] = p.xticks;
    if (!p.xticklabels.empty()) {
      if (p.xticklabels.size() != p.xticks.size())
        throw std::invalid_argument(fmt::format("figure {}: {} x tick labels for {} ticks", f.file,
                                                p.xticklabels.size(), p.xticks.size()));
      pj["xticklabels"] = p.xticklabels;
    }
    json layers = json::array();
    for (const auto& l : p.layers) layers.push_back(layer_json(l));
    pj["layers"] = layers;
    panels.push_back(pj);
  }
  j["panels"] = panels;
  return j;
}

}  // namespace

namespace {

// A segment is one level of a key: a dot in it may only sit inside a number ("range1.5", "pcm@0.001"), never
// separate two names ("dataset.cov_extraction" is two levels, given to under() one at a time).
std::string checked_segment(std::string_view segment) {
  if (segment.empty()) throw std::invalid_argument("Results::under: empty key segment");
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  for (std::size_t i = 0; i < segment.size(); ++i)
    if (segment[i] == '.' &&
        (i == 0 || i + 1 == segment.size() || !digit(segment[i - 1]) || !digit(segment[i + 1])))
      throw std::invalid_argument(fmt::format(
          "Results::under: key segment '{}' holds a dot between names; give each level to under()", segment));
  return std::string(segment);
}

}  // namespace

KeyPath KeyPath::under(std::string_view segment) const {
  KeyPath p;
  p.prefix_ = prefix_ + checked_segment(segment) + ".";
  return p;
}
std::string KeyPath::key(std::string_view field) const {
  if (field.empty())
    throw std::invalid_argument(fmt::format("Results: empty field name under '{}'", prefix_));
  return prefix_ + std::string(field);
}
KeyPath path(std::string_view segment) { return KeyPath().under(segment); }

void Scope::metric(std::string_view field, double value) const { r_->metric(path_.key(field), value); }
void Scope::series(std::string_view field, std::vector<double> values) const {
  r_->series(path_.key(field), std::move(values));
}
void Scope::timing(std::string_view field, double time_s) const { r_->timing(path_.key(field), time_s); }
void Scope::note(std::string_view field, const std::string& text) const { r_->note(path_.key(field), text); }

void Results::metric(const std::string& name, double value) {
  if (name.empty()) throw std::invalid_argument("Results::metric: empty name");
  metrics_[name] = value;
}
void Results::series(const std::string& name, std::vector<double> values) {
  if (name.empty()) throw std::invalid_argument("Results::series: empty name");
  series_[name] = std::move(values);
}
void Results::check(const std::string& name, bool passed, const std::string& detail, bool counted) {
  checks_.push_back({name, passed, detail, counted});
}
void Results::figure(Figure f) {
  if (f.file.empty() || f.file.find('/') != std::string::npos || f.file.find("..") != std::string::npos) {
    throw std::invalid_argument(
        fmt::format("Results::figure: file must be a plain file name, got '{}'", f.file));
  }
  figures_.push_back(std::move(f));
}
void Results::note(const std::string& key, const std::string& text) { notes_[key] = text; }
void Results::timing(const std::string& name, double time_s) { timings_[name] = time_s; }

void write_file_atomic(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  const std::filesystem::path tmp = fmt::format("{}.tmp.{}", path.string(), ::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", tmp.string()));
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(tmp);
      throw std::runtime_error(fmt::format("{}: write failed", tmp.string()));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error(fmt::format("{}: rename failed: {}", path.string(), ec.message()));
  }
}

void Results::write(const std::filesystem::path& path, const Provenance& prov) const {
  json doc;
  doc["id"] = prov.id;
  doc["profile"] = prov.profile;
  json m = json::object();
  for (const auto& [k, v] : metrics_) m[k] = number(v);
  doc["metrics"] = m;
  json s = json::object();
  for (const auto& [k, v] : series_) s[k] = numbers(v);
  doc["series"] = s;
  json c = json::array();
  for (const auto& ch : checks_) {
    json one = {{"name", ch.name}, {"passed", ch.passed}, {"detail", ch.detail}};
    if (!ch.counted) one["counted"] = false;  // absent means counted (older result files stay as they were)
    c.push_back(std::move(one));
  }
  doc["checks"] = c;
  json f = json::array();
  for (const auto& fig : figures_) f.push_back(figure_json(fig));
  doc["figures"] = f;
  if (!notes_.empty()) doc["notes"] = notes_;
  if (!timings_.empty()) {
    json t = json::object();
    for (const auto& [k, v] : timings_) t[k] = round_significant(v, 4);
    doc["timings_s"] = t;
  }
  const std::string hash = fmt::format("{:016x}", prov.config_hash);
  doc["provenance"] = {{"git_sha", prov.git_sha},
                       {"config_hash", hash},
                       {"config_file", prov.config_file},
                       {"compiler", prov.compiler},
                       {"seed", prov.seed},
                       {"profile", prov.profile},
                       {"wall_time_s", round_significant(prov.wall_time_s, 4)},
                       {"threads", prov.threads}};
  if (prov.shards > 0) doc["provenance"]["merged_shards"] = prov.shards;
  const Machine& host = prov.machine;
  json machine = json::object();
  for (const auto& [key, text] : {std::pair<const char*, const std::string*>{"cpu_model", &host.cpu_model},
                                  {"cpu_features", &host.cpu_features},
                                  {"glibc", &host.glibc},
                                  {"blas", &host.blas},
                                  {"lapack", &host.lapack},
                                  {"blas_core", &host.blas_core},
                                  {"overrides", &host.overrides}}) {
    if (!text->empty()) machine[key] = *text;
  }
  if (!host.packages.empty()) machine["packages"] = host.packages;
  if (!machine.empty()) doc["provenance"]["machine"] = machine;
  write_file_atomic(path, doc.dump(1) + "\n");
}

}  // namespace keel::repro
