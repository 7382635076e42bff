// Fig. 3.5 (§3.8) on a SUBSTITUTE: synthetic hull surveys aligned by standardised DVL curvature features.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch3::HullSubstitute>(argc, argv);
}
