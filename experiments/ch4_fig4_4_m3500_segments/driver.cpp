// Figs. 4.4–4.5 (§4.6): SBSOS-SLAM against Levenberg–Marquardt on 100-pose segments of Manhattan3500.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch4::Segments>(argc, argv); }
