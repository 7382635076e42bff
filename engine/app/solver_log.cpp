#include "app/solver_log.hpp"

#include <glog/logging.h>

#include <mutex>
#include <string>
#include <utility>

namespace keel::app {

namespace {

class Sink : public google::LogSink {
 public:
  void set(SolverLogSink sink) {
    std::lock_guard<std::mutex> lock(mutex_);
    sink_ = std::move(sink);
  }
  void send(google::LogSeverity severity, const char* /*full_filename*/, const char* /*base_filename*/,
            int /*line*/, const std::tm* /*time*/, const char* message, std::size_t message_len) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!sink_ || severity < google::GLOG_WARNING) return;
    sink_(severity == google::GLOG_WARNING ? "warning" : "error", std::string_view(message, message_len));
  }

 private:
  std::mutex mutex_;
  SolverLogSink sink_;
};

Sink& the_sink() {
  static Sink sink;
  return sink;
}

}  // namespace

void route_solver_log(SolverLogSink sink) {
  static std::once_flag once;
  std::call_once(once, [] {
    // Initialized glog writes to its log files and to stderr from stderrthreshold up: no file (an empty base
    // name turns a severity's file off), stderr for fatal messages only, the rest through the sink.
    FLAGS_logtostderr = false;
    FLAGS_alsologtostderr = false;
    FLAGS_stderrthreshold = google::GLOG_FATAL;
    for (google::LogSeverity s :
         {google::GLOG_INFO, google::GLOG_WARNING, google::GLOG_ERROR, google::GLOG_FATAL})
      google::SetLogDestination(s, "");
    if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("keel");
    google::AddLogSink(&the_sink());
  });
  FLAGS_minloglevel = sink ? google::GLOG_WARNING : google::GLOG_FATAL;
  the_sink().set(std::move(sink));
}

}  // namespace keel::app
