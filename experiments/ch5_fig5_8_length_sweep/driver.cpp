// Fig. 5.8 (§5.9.1): consistency of composition against trajectory length.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch5::LengthSweep>(argc, argv); }
