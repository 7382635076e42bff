// Beyond Table 3.1 (§3.7): the four alignment methods and the certificate on survey pairs over real terrain.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch3::TerrainComparison>(argc, argv);
}
