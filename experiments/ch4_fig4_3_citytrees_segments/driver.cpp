// Figs. 4.2–4.3 (§4.6): SBSOS-SLAM against Levenberg–Marquardt on 100-pose segments of CityTrees10000
// (landmark SLAM, eq. 4.12).
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch4::Segments>(argc, argv); }
