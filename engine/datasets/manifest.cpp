#include "datasets/manifest.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>

#include "core/config.hpp"
#include "datasets/sha256.hpp"

namespace keel::datasets {

namespace fs = std::filesystem;

const DatasetInfo* DatasetManifest::find_dataset(const std::string& name) const {
  for (const auto& d : datasets)
    if (d.name == name) return &d;
  return nullptr;
}

const DatasetFile* DatasetManifest::find(const std::string& name, const std::string& path) const {
  if (const DatasetInfo* d = find_dataset(name)) {
    for (const auto& f : d->files)
      if (f.path == path) return &f;
  }
  return nullptr;
}

namespace {

bool is_sha256(const std::string& s) {
  return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

bool is_safe_relative(const std::string& p) {
  if (p.empty() || p.front() == '/' || p.find('\\') != std::string::npos) return false;
  for (const auto& part : fs::path(p)) {
    if (part == ".." || part == ".") return false;
  }
  return true;
}

DatasetManifest parse_manifest(const fs::path& file) {
  DatasetManifest m;
  m.file = file;
  const core::ConfigTable root = core::load_toml(file);
  if (root.integer("version") != 1) {
    throw DatasetError(
        fmt::format("{}: unsupported manifest version (this build reads version 1)", root.where("version")));
  }
  const core::ConfigTable all = root.table("datasets");
  for (const auto& name : all.keys()) {
    const core::ConfigTable d = all.table(name);
    DatasetInfo info;
    info.name = name;
    info.title = d.string("title");
    info.citation = d.string("citation");
    const core::ConfigTable files = d.table("files");
    for (const auto& path : files.keys()) {
      const core::ConfigTable f = files.table(path);
      DatasetFile df;
      df.dataset = name;
      df.path = path;
      if (!is_safe_relative(path)) {
        throw DatasetError(fmt::format("{}: a file path must be relative, without '.', '..' or backslashes",
                                       files.where(path)));
      }
      df.sha256 = f.string("sha256");
      if (!is_sha256(df.sha256))
        throw DatasetError(fmt::format("{}: expected 64 lower-case hex digits", f.where("sha256")));
      df.bytes = f.integer("bytes");
      if (df.bytes < 0) throw DatasetError(fmt::format("{}: must be >= 0", f.where("bytes")));
      df.derived = f.has("derived") && f.boolean("derived");
      if (df.derived) {
        df.derived_from = f.strings("derived_from");
        df.generator = f.string("generator");
        df.recipe = f.string("recipe");
        for (const auto& src : df.derived_from) {
          if (!is_safe_relative(src))
            throw DatasetError(fmt::format("{}: '{}' is not a safe path", f.where("derived_from"), src));
        }
      } else if (f.has("system_path")) {
        df.debian_package = f.string("debian_package");
        df.package_version = f.string("package_version");
        df.system_path = f.string("system_path");
        if (!std::filesystem::path(df.system_path).is_absolute())
          throw DatasetError(
              fmt::format("{}: '{}' is not an absolute path", f.where("system_path"), df.system_path));
        df.git_blob = f.string("git_blob");
        df.license = f.string("license");
      } else {
        df.repository = f.string("repository");
        df.commit = f.string("commit");
        df.source_path = f.string("source_path");
        df.git_blob = f.string("git_blob");
        df.license = f.string("license");
      }
      info.files.push_back(std::move(df));
    }
    if (info.files.empty())
      throw DatasetError(fmt::format("{}: a dataset lists at least one file", d.where("files")));
    // Every derived file's inputs are files of the same dataset.
    for (const auto& f : info.files) {
      for (const auto& src : f.derived_from) {
        const bool known = std::any_of(info.files.begin(), info.files.end(),
                                       [&](const DatasetFile& g) { return g.path == src && !g.derived; });
        if (!known) {
          throw DatasetError(
              fmt::format("{}: [datasets.{}.files.\"{}\"] derived_from names '{}', which is not a "
                          "downloadable file of this dataset",
                          file.string(), name, f.path, src));
        }
      }
    }
    m.datasets.push_back(std::move(info));
  }
  root.finish();
  return m;
}

std::mutex& cache_mutex() {
  static std::mutex m;
  return m;
}

// Manifests by path, and verified files by (path, size, mtime): each file is hashed once per process.
std::map<std::string, std::shared_ptr<const DatasetManifest>>& manifest_cache() {
  static std::map<std::string, std::shared_ptr<const DatasetManifest>> c;
  return c;
}
std::map<std::tuple<std::string, std::uintmax_t, long long>, std::string>& hash_cache() {
  static std::map<std::tuple<std::string, std::uintmax_t, long long>, std::string> c;
  return c;
}

std::shared_ptr<const DatasetManifest> cached_manifest(const fs::path& file) {
  const std::string key = fs::absolute(file).lexically_normal().string();
  {
    std::lock_guard<std::mutex> lock(cache_mutex());
    if (auto it = manifest_cache().find(key); it != manifest_cache().end()) return it->second;
  }
  auto m = std::make_shared<const DatasetManifest>(load_dataset_manifest(file));
  std::lock_guard<std::mutex> lock(cache_mutex());
  return manifest_cache().emplace(key, m).first->second;
}

std::string cached_sha256(const fs::path& file, std::uintmax_t size) {
  const std::string key = fs::absolute(file).lexically_normal().string();
  std::error_code ec;
  const auto mtime = fs::last_write_time(file, ec);
  const long long stamp = ec ? 0 : static_cast<long long>(mtime.time_since_epoch().count());
  const auto k = std::make_tuple(key, size, stamp);
  {
    std::lock_guard<std::mutex> lock(cache_mutex());
    if (auto it = hash_cache().find(k); it != hash_cache().end()) return it->second;
  }
  std::string h = sha256_file(file);
  std::lock_guard<std::mutex> lock(cache_mutex());
  hash_cache()[k] = h;
  return h;
}

fs::path root_or_find(const fs::path& root) { return root.empty() ? find_repo_root() : root; }

}  // namespace

DatasetManifest load_dataset_manifest(const fs::path& manifest_toml) {
  try {
    return parse_manifest(manifest_toml);
  } catch (const core::ConfigError& e) {
    throw DatasetError(e.what());
  }
}

fs::path find_repo_root(const fs::path& start) {
  std::error_code ec;
  fs::path dir = start.empty() ? fs::current_path(ec) : fs::absolute(start, ec);
  if (ec) throw DatasetError(fmt::format("cannot determine the current directory: {}", ec.message()));
  const fs::path first = dir;
  for (;;) {
    if (fs::is_regular_file(dir / "datasets" / "manifest.toml", ec)) return dir;
    if (!dir.has_parent_path() || dir.parent_path() == dir) break;
    dir = dir.parent_path();
  }
  throw DatasetError(
      fmt::format("no datasets/manifest.toml in {} or any parent folder: run from inside the keel "
                  "checkout, or pass its root explicitly",
                  first.string()));
}

std::vector<fs::path> dataset_search_paths(const std::string& name, const std::string& relative_path,
                                           const fs::path& root) {
  const fs::path r = root_or_find(root);
  std::vector<fs::path> out;
  if (const char* env = std::getenv("KEEL_DATASETS"); env && *env)
    out.push_back(fs::path(env) / name / relative_path);
  out.push_back(r / "datasets" / "cache" / name / relative_path);
  out.push_back((r / ".." / "shared" / "datasets" / name / relative_path).lexically_normal());
  return out;
}

fs::path resolve_dataset_file(const std::string& name, const std::string& relative_path,
                              const fs::path& root) {
  const fs::path r = root_or_find(root);
  const auto manifest = cached_manifest(r / "datasets" / "manifest.toml");
  const DatasetFile* entry = manifest->find(name, relative_path);
  if (!entry) {
    std::string known;
    if (const DatasetInfo* d = manifest->find_dataset(name)) {
      for (const auto& f : d->files) known += fmt::format("\n  {}", f.path);
      throw DatasetError(fmt::format("{}: dataset '{}' has no file '{}'; its files are:{}",
                                     manifest->file.string(), name, relative_path, known));
    }
    for (const auto& d : manifest->datasets) known += fmt::format("{}{}", known.empty() ? "" : ", ", d.name);
    throw DatasetError(
        fmt::format("{}: no dataset named '{}' (known: {})", manifest->file.string(), name, known));
  }
  std::string report;
  if (const char* env = std::getenv("KEEL_DATASETS"); !env || !*env) {
    report += fmt::format("\n  $KEEL_DATASETS/{}/{}: KEEL_DATASETS is not set", name, relative_path);
  }
  for (const fs::path& p : dataset_search_paths(name, relative_path, r)) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
      report += fmt::format("\n  {}: not found", p.string());
      continue;
    }
    const std::uintmax_t size = fs::file_size(p, ec);
    if (ec) {
      report += fmt::format("\n  {}: cannot read its size ({})", p.string(), ec.message());
      continue;
    }
    if (static_cast<std::int64_t>(size) != entry->bytes) {
      report += fmt::format("\n  {}: {} bytes, the manifest says {}", p.string(), size, entry->bytes);
      continue;
    }
    std::string got;
    try {
      got = cached_sha256(p, size);
    } catch (const std::exception& e) {
      report += fmt::format("\n  {}: {}", p.string(), e.what());
      continue;
    }
    if (got != entry->sha256) {
      report +=
          fmt::format("\n  {}: sha256 {} differs from the manifest's {}", p.string(), got, entry->sha256);
      continue;
    }
    return p;
  }
  std::string how = fmt::format(
      "\nFetch it with: scripts/fetch-datasets {} (downloads into datasets/cache/; --from "
      "DIR copies from a local mirror laid out like shared/datasets), or set KEEL_DATASETS "
      "to a folder holding <name>/<path>.",
      name);
  if (!entry->system_path.empty())
    how += fmt::format(
        "\nThis file is installed by the Debian package {} {} at {}: scripts/fetch-datasets {} copies it "
        "(scripts/setup installs the package and runs that).",
        entry->debian_package, entry->package_version, entry->system_path, name);
  if (entry->derived) {
    how += fmt::format(
        "\nThis file is derived here (not downloadable): scripts/fetch-datasets {} regenerates it from ",
        name);
    for (std::size_t k = 0; k < entry->derived_from.size(); ++k)
      how += fmt::format("{}{}", k ? ", " : "", entry->derived_from[k]);
    how += " and checks its sha256.";
  }
  throw DatasetError(fmt::format("dataset file {}/{} (sha256 {}...) has no verified copy; looked in:{}{}",
                                 name, relative_path, entry->sha256.substr(0, 12), report, how));
}

}  // namespace keel::datasets
