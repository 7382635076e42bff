// Beyond the thesis: the robust back end (PCM per robot and pair, residual check, certified solve) on real
// graphs with wrong loop closures, one robot or several.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch4::RobustBackend>(argc, argv);
}
