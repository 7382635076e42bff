// Beyond Table 3.1 (§3.7): the four alignment methods on a grid of regimes fixed in advance (README: five
// cells repeat earlier runs).
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch3::RegimeGrid>(argc, argv); }
