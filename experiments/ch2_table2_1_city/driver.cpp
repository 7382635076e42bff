// Table 2.1 and Fig. 2.5 (§2.7.2): robust merging of a two-robot split of City10000 with DCS, SCGP, RANSAC
// and PCM — thin driver over keel.graph (data), keel.pcm (scenario, consistency, selection, map merging) and
// keel.core.
import keel.core;
import keel.lie;
import keel.graph;
import keel.pgo;
import keel.cov;
import keel.pcm;
import keel.sim;
import keel.eval;

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/two_robot.hpp"
#include "common/city_table.hpp"

int main(int argc, char** argv) {
  return keel::core::experiment_main(argc, argv, keel::experiments::run_city_merge_table);
}
