// Beyond the thesis: the dual certificate of global optimality of keel.pgo's solution of a whole planar data
// set (Carlone et al. 2016 / SE-Sync).
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch4::WholeDataCertificate>(argc, argv);
}
