// Beyond the thesis: exact, heuristic and densest-subgraph maximum clique at scale (planted cliques, 1D
// worlds, the Table 2.1 candidate sets).
import keel.repro;
import keel.study;

int main(int argc, char** argv) { return keel::repro::study_main<keel::study::ch2::CliqueScale>(argc, argv); }
