// Theorems 4.5.3–4.5.4: is Sparse-BSOS at d = k = 1 exact? A counterexample and random small graphs, with
// escalation to order 2.
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch4::Exactness>(argc, argv); }
