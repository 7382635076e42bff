// Beyond the thesis: the certified solve on corrupted subsets of SE-Sync's benchmark graphs (noise sweep).
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch4::CertifiedNoiseSweep>(argc, argv);
}
