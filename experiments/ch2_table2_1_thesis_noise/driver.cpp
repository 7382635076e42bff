// Table 2.1 (§2.7.2) in the thesis's noise regime: the City10000 two-robot data sets with every measurement
// redrawn.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch2::CityTable>(argc, argv); }
