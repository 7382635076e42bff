// The data sets in unit tests, one policy: a test case that reads a benchmark file is in the doctest suite
// "datasets" (`TEST_CASE("..." * doctest::test_suite("datasets"))`), which keel_area() registers as the CTest
// entry datasets.<area> with the label "datasets" (unit.<area> excludes the suite), and it finds its files
// through dataset_file(): without a verified copy that fails the test case, naming the missing file and the
// command that fetches it. A test that needs data never passes without it. Include it as
// "kit/dataset_files.hpp"; the area's unit tests link keel_datasets_impl (TEST_DEPENDS in its
// CMakeLists.txt).
#pragma once

#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "datasets/manifest.hpp"

namespace keel::testkit {

// The verified copy of file `path` of data set `name` (datasets::resolve_dataset_file; `root` empty: the
// checkout around the working directory). Without one, FAILs the running test case with the resolver's report
// (every place looked in and what was wrong there) and the fetch command.
inline std::filesystem::path dataset_file(const std::string& name, const std::string& path,
                                          const std::filesystem::path& root = {}) {
  try {
    return datasets::resolve_dataset_file(name, path, root);
  } catch (const datasets::DatasetError& e) {
    FAIL("this test needs the data set file ", name, "/", path,
         ", which has no verified copy here: fetch it with scripts/fetch-datasets ", name, "\n",
         std::string(e.what()));
    throw;  // not reached: FAIL ends the test case
  }
}

}  // namespace keel::testkit
