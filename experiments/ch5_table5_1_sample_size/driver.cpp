// Tables 5.1–5.2, §5.9.2: the mean covariance errors against the Monte-Carlo sample size M.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch5::PairSampleSize>(argc, argv);
}
