// Fig. 2.3 (§2.7.1.2): selection time against the number of measurements on simulated 1D worlds.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch2::Timing>(argc, argv); }
