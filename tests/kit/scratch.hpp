// A scratch folder for tests that write files: a fresh temporary root named after the test and the process,
// removed with the fixture (engine/core/core_test.cpp, engine/repro/repro_test.cpp,
// engine/repro/shard_test.cpp).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <string>

namespace keel::testkit {

struct Scratch {
  std::filesystem::path root;
  explicit Scratch(const std::string& tag) {
    root = std::filesystem::temp_directory_path() / fmt::format("keel_test_{}_{}", tag, ::getpid());
    std::filesystem::remove_all(root);
    std::filesystem::create_directories(root);
  }
  ~Scratch() { std::filesystem::remove_all(root); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  // Writes `text` to root/rel, creating its folders; returns the path.
  std::filesystem::path write(const std::string& rel, const std::string& text) const {
    const std::filesystem::path p = root / rel;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }
};

}  // namespace keel::testkit
