// Table 2.1 and Fig. 2.5 (§2.7.2): robust merging of a two-robot split of City10000 with DCS, SCGP, RANSAC
// and PCM.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch2::CityTable>(argc, argv); }
