// Beyond Fig. 2.2 (§2.7.1.1): PCM-Heuristic's and PCM-Exact's match rate as the 1D worlds get denser.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch2::DensitySweep>(argc, argv);
}
