// keel::graph — the dataset manifest (datasets/manifest.toml) and the resolver that finds a verified copy of
// a file.
//
// resolve_dataset_file(name, path) looks, in order, in
//   1. $KEEL_DATASETS/<name>/<path>
//   2. <repo>/datasets/cache/<name>/<path>          (where scripts/fetch-datasets puts downloads)
//   3. <repo>/../shared/datasets/<name>/<path>      (the shared copy next to the checkout)
// and returns the first file whose sha256 equals the manifest's (checked once per file per process). <repo>
// is the explicit root, or else the nearest ancestor of the current directory that contains
// datasets/manifest.toml. When no place holds a good copy it throws DatasetError listing every place and what
// was wrong there, and how to fetch it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace keel::datasets {

class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DatasetFile {
  std::string dataset;  // e.g. "manhattan3500"
  std::string path;     // relative to the dataset folder, e.g. "isam/manhattanOlson3500.txt"
  std::string sha256;   // lower-case hex
  std::int64_t bytes = 0;
  bool derived = false;         // made here (not downloadable): see recipe / derived_from
  std::string repository;       // "owner/name" on GitHub (empty when derived or installed)
  std::string commit;           // pinned commit of the snapshot
  std::string source_path;      // path in the source repository
  std::string debian_package;   // installed by this Debian package instead (scripts/fetch-datasets copies it)
  std::string package_version;  // the package version whose file the sha256 pins
  std::string system_path;      // where the package installs it (absolute)
  std::string git_blob;         // `git hash-object` of the file (a second, independent pin)
  std::string license;          // what the source states
  std::vector<std::string> derived_from;  // derived files: the inputs (paths in the same dataset)
  std::string generator;  // derived files: the procedure of scripts/fetch-datasets that remakes it
  std::string recipe;     // derived files: how they were made
};

struct DatasetInfo {
  std::string name;
  std::string title;
  std::string citation;
  std::vector<DatasetFile> files;
};

struct DatasetManifest {
  std::filesystem::path file;
  std::vector<DatasetInfo> datasets;
  const DatasetInfo* find_dataset(const std::string& name) const;
  const DatasetFile* find(const std::string& name, const std::string& path) const;
};

/// Strict: unknown keys, missing keys, a malformed sha256 and duplicate files are DatasetErrors (or core
/// ConfigErrors re-thrown as DatasetError) naming the manifest, the table and the key.
DatasetManifest load_dataset_manifest(const std::filesystem::path& manifest_toml);

/// Nearest ancestor of `start` (default: the current directory) that contains datasets/manifest.toml.
std::filesystem::path find_repo_root(const std::filesystem::path& start = {});

/// See the header comment. `root` empty = find_repo_root().
std::filesystem::path resolve_dataset_file(const std::string& name, const std::string& relative_path,
                                           const std::filesystem::path& root = {});

/// Where resolve_dataset_file looks, in order (existing or not), for messages and scripts.
std::vector<std::filesystem::path> dataset_search_paths(const std::string& name,
                                                        const std::string& relative_path,
                                                        const std::filesystem::path& root = {});

}  // namespace keel::datasets
