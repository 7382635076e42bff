// Beyond the thesis: certified pose-graph optimization of the isotropic model on SE-Sync's benchmark graphs.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch4::CertifiedBenchmark>(argc, argv);
}
