// Fig. 5.7 (§5.8.1): the SSC prediction of Fig. 5.4 converted to the Lie algebra by the unscented transform.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch5::UnscentedSsc>(argc, argv);
}
