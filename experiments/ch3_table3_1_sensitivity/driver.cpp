// Beyond Table 3.1 (§3.7): the four alignment methods against feature noise and query size.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch3::Sensitivity>(argc, argv); }
