// Fig. 5.4 (§5.5.2): composition of correlated odometry, SSC against the Lie algebra.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch5::Composition>(argc, argv); }
