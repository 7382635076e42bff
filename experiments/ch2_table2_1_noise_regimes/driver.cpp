// Table 2.1 (§2.7.2) against the noise of redrawn measurements, and the calibration of Q.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch2::NoiseRegimes>(argc, argv);
}
