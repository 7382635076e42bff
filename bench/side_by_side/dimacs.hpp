// The DIMACS "p edge" reader the side-by-side drivers share (keel_clique.cpp, clipper_clique.cpp): C++17 and
// no keel header, so it builds against every keel revision clique.sh compares and with CLIPPER's compiler.
#pragma once

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace side_by_side {

struct DimacsGraph {
  std::string name;  // the file name without its directory and ".clq"
  int n = 0;
  std::vector<std::pair<int, int>> edges;  // 0-based, u < v, sorted, no duplicates
};

// Lines: "c …" comments, one "p edge N M", then "e u v" with 1-based vertices. Throws std::runtime_error
// naming the file and line of anything else.
inline DimacsGraph read_dimacs(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  DimacsGraph g;
  g.name = path.substr(path.find_last_of('/') + 1);
  g.name = g.name.substr(0, g.name.rfind(".clq"));
  std::string line;
  int n = -1;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == 'c') continue;
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "p") {
      std::string format;
      long long m = 0;
      if (!(s >> format >> n >> m) || n < 0) throw std::runtime_error(path + ": bad problem line");
      g.edges.reserve(static_cast<std::size_t>(m));
    } else if (tag == "e") {
      int u = 0, v = 0;
      if (n < 0 || !(s >> u >> v) || u < 1 || v < 1 || u > n || v > n || u == v)
        throw std::runtime_error(path + ":" + std::to_string(number) + ": bad edge line");
      g.edges.emplace_back(std::min(u, v) - 1, std::max(u, v) - 1);
    } else {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": unknown line tag '" + tag + "'");
    }
  }
  if (n < 0) throw std::runtime_error(path + ": no problem line");
  g.n = n;
  std::sort(g.edges.begin(), g.edges.end());
  g.edges.erase(std::unique(g.edges.begin(), g.edges.end()), g.edges.end());
  return g;
}

}  // namespace side_by_side
