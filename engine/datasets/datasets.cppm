// keel.datasets — the curated facade of engine/datasets (tier "data", docs/DESIGN.md "Tiers"): the dataset
// manifest (datasets/manifest.toml) and the resolver that finds a sha256-verified copy of a benchmark file.
// Facade rules as every area.
module;
#include "datasets/manifest.hpp"
#include "datasets/sha256.hpp"
export module keel.datasets;

export namespace keel::datasets {
using keel::datasets::dataset_search_paths;
using keel::datasets::DatasetError;
using keel::datasets::DatasetFile;
using keel::datasets::DatasetInfo;
using keel::datasets::DatasetManifest;
using keel::datasets::find_repo_root;
using keel::datasets::load_dataset_manifest;
using keel::datasets::resolve_dataset_file;
using keel::datasets::Sha256;
using keel::datasets::sha256_file;
using keel::datasets::sha256_hex;
}  // namespace keel::datasets
