// Fig. 2.4 (§2.7.2.1): TPR, FPR and normalized χ² against the consistency threshold on the City10000
// two-robot data sets.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch2::ThresholdSweep>(argc, argv);
}
