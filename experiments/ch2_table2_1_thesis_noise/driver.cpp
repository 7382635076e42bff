// Table 2.1 (§2.7.2) in the thesis's noise regime: the City10000 two-robot data sets with every measurement
// redrawn and PCM — thin driver over keel.eval's two-robot study (common/city_table.hpp).
import keel.core;
import keel.repro;
import keel.pcm;
import keel.merge;
import keel.eval;

#include "common/two_robot.hpp"
#include "common/city_table.hpp"

int main(int argc, char** argv) {
  return keel::repro::experiment_main(argc, argv, keel::experiments::run_city_merge_table);
}
