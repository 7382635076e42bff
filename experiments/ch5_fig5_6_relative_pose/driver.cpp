// Figs. 5.5–5.6 (§5.7.2): relative pose of two correlated poses.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch5::RelativePose>(argc, argv);
}
