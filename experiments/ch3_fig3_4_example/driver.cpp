// Fig. 3.4 (§3.7): one simulated world of Table 3.1 and the four methods' estimates.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch3::Example>(argc, argv); }
