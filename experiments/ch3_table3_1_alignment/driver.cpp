// Table 3.1 (§3.7): the four convex alignment methods on simulated worlds; beyond the thesis, the certified
// optimum over SO(2) of round 0.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch3::AlignmentComparison>(argc, argv);
}
