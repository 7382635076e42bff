// keel::sim — the keel grid file reader (terrain.hpp): the text read once and parsed from memory, every count
// and value through core::parse_integer / core::parse_real, errors located as graph::ParseError.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/parse.hpp"
#include "graph/parse_error.hpp"
#include "sim/terrain.hpp"

namespace keel::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Reads the file's lines (the text read once, so a pipe works), numbered, for located errors.
struct GridReader {
  std::string file;
  std::istringstream in;
  int line = 0;
  [[noreturn]] void fail(const std::string& what) const { throw graph::ParseError(file, line, what); }
  std::string next(const char* expecting) {
    std::string text;
    if (!std::getline(in, text)) fail(fmt::format("the file ends where {} was expected", expecting));
    ++line;
    return text;
  }
  // A "key rest" line: returns rest.
  std::string keyed(const std::string& key) {
    const std::string text = next(fmt::format("the '{}' line", key).c_str());
    if (text.rfind(key, 0) != 0 || (text.size() > key.size() && text[key.size()] != ' '))
      fail(fmt::format("expected a '{}' line, found '{}'", key, text.substr(0, 40)));
    return text.size() > key.size() ? text.substr(key.size() + 1) : std::string();
  }
  std::vector<double> numbers(const std::string& text, std::size_t count, const char* what) {
    std::istringstream s(text);
    std::vector<double> v;  // not reserved: `count` is checked against the values actually there
    std::string token;
    while (s >> token) {
      double x = 0;
      if (auto why = core::parse_real(token, x); !why.empty())
        fail(fmt::format("{} value {}: {}", what, v.size() + 1, why));
      v.push_back(x);
    }
    if (v.size() != count) fail(fmt::format("{} values: {} where {} were expected", what, v.size(), count));
    return v;
  }
  std::size_t count(const std::string& key) {
    const std::string text = keyed(key);
    std::int64_t n = 0;
    if (auto why = core::parse_integer(text, 3, std::int64_t{1} << 30, n, "a node count"); !why.empty())
      fail(fmt::format("{}: {}", key, why));
    return static_cast<std::size_t>(n);
  }
};

// +1 when v strictly increases, −1 when it strictly decreases, 0 otherwise.
int monotonic(const std::vector<double>& v) {
  bool up = true, down = true;
  for (std::size_t k = 1; k < v.size(); ++k) up = up && v[k] > v[k - 1], down = down && v[k] < v[k - 1];
  return up ? 1 : (down ? -1 : 0);
}

}  // namespace

TerrainGrid parse_terrain_grid(std::string text, const std::string& name) {
  GridReader r{name, std::istringstream(std::move(text)), 0};
  if (r.next("the header") != "keel-grid 1")
    r.fail("not a keel grid file (the first line must be 'keel-grid 1')");
  TerrainGrid g;
  g.source = r.keyed("source");
  const std::size_t rows = r.count("rows"), cols = r.count("cols");
  std::vector<double> lon = r.numbers(r.keyed("lon"), cols, "lon");
  const int lon_line = r.line;
  std::vector<double> lat = r.numbers(r.keyed("lat"), rows, "lat");
  const int lat_line = r.line;
  if (const std::string units = r.keyed("z_units"); units != "m")
    r.fail(fmt::format("z_units '{}': only m", units));
  if (!r.keyed("values").empty()) r.fail("the 'values' line takes nothing after it");
  // Grown row by row as the values are read (rows × cols is not allocated before the file holds that many).
  std::vector<double> z;
  for (std::size_t i = 0; i < rows; ++i) {
    const std::vector<double> row =
        r.numbers(r.next("a row of values"), cols, fmt::format("row {}", i + 1).c_str());
    z.insert(z.end(), row.begin(), row.end());
  }
  const int sx = monotonic(lon), sy = monotonic(lat);
  if (sx == 0) {
    r.line = lon_line;
    r.fail("the longitudes are not strictly monotonic");
  }
  if (sy == 0) {
    r.line = lat_line;
    r.fail("the latitudes are not strictly monotonic");
  }
  if (std::abs(lat.front()) > 89 || std::abs(lat.back()) > 89) {
    r.line = lat_line;
    r.fail("latitudes beyond ±89°: the equirectangular projection does not hold there");
  }
  if (std::abs(lon.front()) > 360 || std::abs(lon.back()) > 360) {
    r.line = lon_line;
    r.fail("longitudes beyond ±360°");
  }
  // Projected about the middle of the extent; rows and columns reordered so x and y increase.
  g.lon0 = 0.5 * (lon.front() + lon.back()), g.lat0 = 0.5 * (lat.front() + lat.back());
  const double kx = kEarthRadius * std::cos(g.lat0 * kPi / 180) * kPi / 180, ky = kEarthRadius * kPi / 180;
  g.x.resize(cols), g.y.resize(rows), g.z.resize(rows * cols);
  for (std::size_t c = 0; c < cols; ++c) g.x[c] = kx * (lon[sx > 0 ? c : cols - 1 - c] - g.lon0);
  for (std::size_t i = 0; i < rows; ++i) g.y[i] = ky * (lat[sy > 0 ? i : rows - 1 - i] - g.lat0);
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t c = 0; c < cols; ++c)
      g.z[i * cols + c] = z[(sy > 0 ? i : rows - 1 - i) * cols + (sx > 0 ? c : cols - 1 - c)];
  // Nodes closer than a rounding unit of the projected metres would make cells of width 0.
  if (monotonic(g.x) != 1) {
    r.line = lon_line;
    r.fail("the longitudes are too close together to tell apart once projected to metres");
  }
  if (monotonic(g.y) != 1) {
    r.line = lat_line;
    r.fail("the latitudes are too close together to tell apart once projected to metres");
  }
  return g;
}

TerrainGrid read_terrain_grid(const std::filesystem::path& file) {
  std::string text;
  if (auto why = core::read_whole_file(file, text); !why.empty())
    throw graph::ParseError(file.string(), 0, fmt::format("the grid file: {}", why));
  return parse_terrain_grid(std::move(text), file.string());
}

}  // namespace keel::sim
