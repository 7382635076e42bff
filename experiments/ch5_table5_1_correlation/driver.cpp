// Table 5.1 and Figs. 5.10–5.14 (a–e), §5.9.2: relative-pose covariance error with and without correlation.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch5::PairCorrelation>(argc, argv);
}
