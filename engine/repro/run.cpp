#include "repro/run.hpp"

namespace keel::repro {

RunContext::RunContext(core::Streams streams, unsigned threads, std::string label, int progress)
    : streams_(streams),
      threads_(threads == 0 ? core::default_threads() : threads),
      label_(std::move(label)),
      progress_(progress) {}

RunContext RunContext::with_streams(core::Streams streams) const {
  RunContext c = *this;
  c.streams_ = streams;
  return c;
}

RunContext RunContext::with_threads(unsigned threads) const {
  RunContext c = *this;
  c.threads_ = threads == 0 ? core::default_threads() : threads;
  return c;
}

RunContext run_context(const Experiment& ex) {
  return RunContext(core::Streams(ex.seed()), ex.threads(), ex.id(), -1);
}

}  // namespace keel::repro
