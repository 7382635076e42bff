// Table 2.2 and Figs. 2.6–2.7 (§2.7.3) on a SUBSTITUTE: a two-robot split of sphere2500.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch2::Substitute3D>(argc, argv);
}
