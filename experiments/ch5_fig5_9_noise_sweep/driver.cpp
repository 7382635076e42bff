// Fig. 5.9 (§5.9.1): consistency of composition against rotation and translation noise.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch5::NoiseSweep>(argc, argv); }
