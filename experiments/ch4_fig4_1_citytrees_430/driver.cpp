// Fig. 4.1 (§4.6): the first 430 poses of CityTrees10000, SBSOS-SLAM certified against LM from a random
// start.
import keel.repro;
import keel.study;

int main(int argc, char** argv) {
  return keel::repro::study_main<keel::study::ch4::FirstSegment>(argc, argv);
}
