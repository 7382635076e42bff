// Table 5.2 and Figs. 5.10–5.14 (f–g), §5.9.2: normalized relative-pose covariance error, proposed vs SSC.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch5::PairsVsSsc>(argc, argv); }
