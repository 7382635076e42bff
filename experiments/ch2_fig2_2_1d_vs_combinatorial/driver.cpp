// Fig. 2.2 (§2.7.1.1): PCM-Exact, PCM-Heuristic, SCGP and RANSAC against the combinatorial maximum pairwise
// consistent set (eq. 2.5) on simulated 1D worlds.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch2::World1DComparison>(argc, argv);
}
