#include "app/outputs.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

#include "graph/io.hpp"

namespace keel::app {

namespace fs = std::filesystem;

namespace {

std::string reason(int error) { return std::strerror(error); }

// The path an output is renamed onto: a symbolic link is followed, so the file it points to is replaced and
// the link kept.
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(p, ec))) {
    const fs::path c = fs::canonical(p, ec);
    if (!ec) return c;
  }
  return p;
}

// An absolute, normalized spelling of p (existing parts resolved), to compare outputs with each other.
fs::path absolute_spelling(const fs::path& p) {
  std::error_code ec;
  fs::path w = fs::weakly_canonical(p, ec);
  if (ec) w = fs::absolute(p, ec).lexically_normal();
  return w;
}

// The first 64 KiB of a file.
bool read_head(const fs::path& file, std::string& head) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  head.assign(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return !in.bad();
}

// The mode a file created by open(2) with 0666 gets under the process's umask (mkstemp creates 0600).
mode_t new_file_mode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

// The temporaries a signal handler removes: fixed storage written before a slot is marked used, so the
// handler only reads it and calls async-signal-safe functions (unlink, rmdir, raise).
struct SignalSlot {
  std::atomic<bool> used{false};
  bool folder = false;
  char path[4096] = {};
};
constexpr int kSignalSlots = 256;
SignalSlot g_signal_slots[kSignalSlots];
std::atomic<int> g_signal_slot_count{0};

int register_temporary(const fs::path& p, bool folder) {
  const std::string s = p.string();
  if (s.size() >= sizeof(SignalSlot::path)) return -1;
  const int k = g_signal_slot_count.fetch_add(1);
  if (k >= kSignalSlots) return -1;
  std::memcpy(g_signal_slots[k].path, s.c_str(), s.size() + 1);
  g_signal_slots[k].folder = folder;
  g_signal_slots[k].used.store(true);
  return k;
}

extern "C" void remove_temporaries_and_reraise(int sig) {
  const int n = std::min(g_signal_slot_count.load(), kSignalSlots);
  for (int k = 0; k < n; ++k)  // files first, then folders (empty by then), the innermost first
    if (g_signal_slots[k].used.load() && !g_signal_slots[k].folder) ::unlink(g_signal_slots[k].path);
  for (int k = n - 1; k >= 0; --k)
    if (g_signal_slots[k].used.load() && g_signal_slots[k].folder) ::rmdir(g_signal_slots[k].path);
  ::raise(sig);  // SA_RESETHAND restored the default action
}

}  // namespace

void remove_temporaries_on_signals() {
  struct sigaction action = {};
  action.sa_handler = remove_temporaries_and_reraise;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &action, nullptr);
}

std::string OutputKind::describe() const {
  switch (type) {
    case Type::json:
      return "a JSON document";
    case Type::graph:
      return "a pose graph (g2o or iSAM)";
    case Type::first_line:
      break;
  }
  return fmt::format("a file whose first line starts with '{}'", first_line);
}

bool OutputKind::matches(std::string_view head, const fs::path& file) const {
  switch (type) {
    case Type::json: {
      const auto k = head.find_first_not_of(" \t\r\n");
      return k != std::string_view::npos && head[k] == '{';
    }
    case Type::graph:
      try {
        return graph::detect_graph_format(head.substr(0, head.rfind('\n') + 1), file).has_value();
      } catch (const std::exception&) {
        return false;
      }
    case Type::first_line:
      break;
  }
  return head.starts_with(first_line);
}

std::vector<FolderFile> split_folder_files() {
  // The first lines are those app::split_files writes.
  return {{"a.g2o", OutputKind::graph()},
          {"b.g2o", OutputKind::graph()},
          {"candidates.g2o", OutputKind::graph()},
          {"labels.txt", OutputKind::starting_with("# candidate kind group")},
          {"truth.txt", OutputKind::starting_with("# T_ab")}};
}

std::vector<FolderFile> robot_folder_files(int robots) {
  std::vector<FolderFile> files;
  for (int r = 0; r < robots; ++r) files.push_back({fmt::format("robot{}.g2o", r), OutputKind::graph()});
  if (robots > 1) files.push_back({"candidates.g2o", OutputKind::graph()});
  files.push_back({"closures.txt", OutputKind::starting_with("# i j file edge kind")});
  return files;
}

std::vector<FolderFile> world_folder_files() {
  // The headers app::write_survey_csv and the world writer put on the first line.
  return {{"reference.csv", OutputKind::starting_with("x,y")},
          {"query.csv", OutputKind::starting_with("x,y")},
          {"truth.csv", OutputKind::starting_with("theta,tx,ty")}};
}

void check_folder_writable(const std::string& name, const fs::path& dir) {
  std::error_code ec;
  fs::path existing = dir.empty() ? fs::path(".") : dir;
  while (!fs::exists(existing, ec) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  if (existing.empty() || !fs::exists(existing, ec)) existing = ".";
  if (!fs::is_directory(existing, ec))
    throw OutputError(
        fmt::format("{}: {} cannot be created: {} is not a folder", dir.string(), name, existing.string()));
  std::string pattern = (existing / ".keel-XXXXXX").string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0)
    throw OutputError(fmt::format("{}: cannot write: {} (creating a file in {})", dir.string(), reason(errno),
                                  existing.string()));
  ::close(fd);
  ::unlink(pattern.c_str());
}

Outputs::Outputs(std::vector<std::pair<std::string, fs::path>> inputs) {
  for (auto& [name, path] : inputs) {
    std::error_code ec;
    if (!path.empty() && fs::exists(path, ec)) inputs_.emplace_back(std::move(name), std::move(path));
  }
}

Outputs::~Outputs() {
  for (int k : signal_slots_)
    if (k >= 0) g_signal_slots[k].used.store(false);
  if (committed_) return;
  std::error_code ec;
  for (const auto& f : files_) {
    fs::remove(f.temporary, ec);
    fs::remove(f.temporary.string() + ".tmp", ec);  // a graph writer's own stage, if it was interrupted
  }
  for (const auto& d : folders_) fs::remove_all(d.temporary, ec);
  for (auto it = created_dirs_.rbegin(); it != created_dirs_.rend(); ++it) fs::remove(*it, ec);  // if empty
}

void Outputs::check_target(const std::string& name, const fs::path& target, const OutputKind& kind,
                           bool folder_member) {
  const std::string t = target.string();
  std::error_code ec;
  const bool exists = fs::exists(target, ec);
  if (exists) {
    for (const auto& [input_name, input] : inputs_) {
      std::error_code eq;
      if (fs::equivalent(target, input, eq))
        throw OutputError(fmt::format("{}: {} is the input {} ({}); refusing to write over an input", t, name,
                                      input_name, input.string()));
    }
  }
  const fs::path spelling = absolute_spelling(target);
  for (const auto& [other, path] : claimed_) {
    if (path == spelling)
      throw OutputError(fmt::format("{}: given for two outputs ({} and {})", t, other, name));
  }
  if (exists) {
    const auto st = fs::status(target, ec);
    if (!fs::is_regular_file(st))
      throw OutputError(
          fmt::format("{}: {} exists and is not a regular file; refusing to replace it", t, name));
    if (::access(target.c_str(), W_OK) != 0)
      throw OutputError(fmt::format("{}: cannot write: {}", t, reason(errno)));
    std::string head;
    if (!read_head(target, head))
      throw OutputError(
          fmt::format("{}: {} exists and cannot be read to check what it holds: {}", t, name, reason(errno)));
    if (!head.empty() && !kind.matches(head, target))
      throw OutputError(fmt::format(
          "{}: {} exists and is not {}{}; refusing to replace it (give a new path, or remove the file)", t,
          name, kind.describe(), folder_member ? " as this command writes it" : ""));
  }
  claimed_.emplace_back(name, spelling);
}

fs::path Outputs::file(const std::string& name, const fs::path& target, OutputKind kind) {
  if (target.empty()) throw OutputError(fmt::format("{}: an empty path", name));
  check_target(name, target, kind, false);
  const fs::path real = resolved(target);
  const fs::path dir = real.parent_path().empty() ? fs::path(".") : real.parent_path();
  const std::string ext = real.extension().string();
  std::string pattern = (dir / fmt::format(".{}.keel-XXXXXX{}", real.filename().string(), ext)).string();
  const int fd = ::mkstemps(pattern.data(), static_cast<int>(ext.size()));
  if (fd < 0)
    throw OutputError(fmt::format("{}: cannot write: {} (creating a file in {})", target.string(),
                                  reason(errno), dir.string()));
  ::fchmod(fd, new_file_mode());
  ::close(fd);
  std::error_code ec;
  const auto existing = fs::status(real, ec);
  // A graph writer may stage through "<temporary>.tmp" itself.
  signal_slots_.push_back(register_temporary(pattern, false));
  signal_slots_.push_back(register_temporary(pattern + ".tmp", false));
  files_.push_back(
      {target, pattern, false, fs::is_regular_file(existing) ? existing.permissions() : fs::perms::unknown});
  return pattern;
}

fs::path Outputs::folder(const std::string& name, const fs::path& dir, const std::vector<FolderFile>& files) {
  if (dir.empty()) throw OutputError(fmt::format("{}: an empty path", name));
  std::error_code ec;
  const auto st = fs::status(dir, ec);
  const bool exists = fs::exists(st);
  if (exists && !fs::is_directory(st))
    throw OutputError(fmt::format("{}: {} exists and is not a folder", dir.string(), name));
  std::vector<std::string> present, missing, names;
  for (const auto& f : files) {
    (fs::exists(dir / f.name, ec) || fs::is_symlink(fs::symlink_status(dir / f.name, ec)) ? present : missing)
        .push_back(f.name);
    names.push_back(f.name);
  }
  // Files of these names are replaced only as a whole set: a folder an earlier run of the command wrote.
  if (!present.empty() && !missing.empty())
    throw OutputError(fmt::format(
        "{}: {} holds {} but not {}, so it is not a folder this command wrote; refusing to replace {} (give "
        "a "
        "new or empty folder)",
        dir.string(), name, fmt::join(present, ", "), fmt::join(missing, ", "), fmt::join(present, ", ")));
  for (const auto& f : files) check_target(name, dir / f.name, f.kind, true);
  if (!exists) {
    // Remember the folders created here, to remove them again if the command fails.
    std::vector<fs::path> chain;
    for (fs::path p = fs::absolute(dir, ec); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
      chain.push_back(p);
      if (p == p.parent_path()) break;
    }
    fs::create_directories(dir, ec);
    if (ec) throw OutputError(fmt::format("{}: cannot create the folder: {}", dir.string(), ec.message()));
    created_dirs_.insert(created_dirs_.end(), chain.rbegin(), chain.rend());
    for (auto it = chain.rbegin(); it != chain.rend(); ++it)
      signal_slots_.push_back(register_temporary(*it, true));
  }
  std::string pattern = (dir / ".keel-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw OutputError(fmt::format("{}: cannot write: {}", dir.string(), reason(errno)));
  signal_slots_.push_back(register_temporary(pattern, true));
  for (const auto& n : names) {
    signal_slots_.push_back(register_temporary(fs::path(pattern) / n, false));
    signal_slots_.push_back(register_temporary(fs::path(pattern) / (n + ".tmp"), false));
  }
  folders_.push_back({dir, pattern, names});
  return pattern;
}

Outputs::File& Outputs::reserved(const fs::path& target) {
  for (auto& f : files_)
    if (f.target == target) return f;
  throw std::logic_error(fmt::format("Outputs: {} was not reserved", target.string()));
}

void Outputs::write(const fs::path& target, const std::function<void(const fs::path&)>& writer) {
  File& f = reserved(target);
  try {
    writer(f.temporary);
    f.written = true;
  } catch (const OutputError&) {
    throw;
  } catch (const std::exception& e) {
    throw OutputError(fmt::format("{}: cannot write: {}", target.string(), e.what()));
  }
}

void Outputs::write_text(const fs::path& target, std::string_view text) {
  File& f = reserved(target);
  std::FILE* out = std::fopen(f.temporary.c_str(), "wb");
  if (out == nullptr) throw OutputError(fmt::format("{}: cannot write: {}", target.string(), reason(errno)));
  const bool written = std::fwrite(text.data(), 1, text.size(), out) == text.size() && std::fflush(out) == 0;
  const int error = errno;
  if (std::fclose(out) != 0 || !written)
    throw OutputError(fmt::format("{}: cannot write: {}", target.string(), reason(written ? errno : error)));
  f.written = true;
}

void Outputs::commit() {
  for (const auto& f : files_)
    if (!f.written)
      throw std::logic_error(fmt::format("Outputs: {} was reserved but not written", f.target.string()));
  for (const auto& f : files_) {
    std::error_code ec;
    if (f.mode != fs::perms::unknown) fs::permissions(f.temporary, f.mode, ec);
    if (std::rename(f.temporary.c_str(), resolved(f.target).c_str()) != 0)
      throw OutputError(fmt::format("{}: cannot write: {} (renaming {} into place)", f.target.string(),
                                    reason(errno), f.temporary.string()));
  }
  for (const auto& d : folders_) {
    for (const auto& name : d.names) {
      const fs::path from = d.temporary / name, to = resolved(d.dir / name);
      if (std::rename(from.c_str(), to.c_str()) != 0)
        throw OutputError(fmt::format("{}: cannot write: {}", to.string(), reason(errno)));
    }
    std::error_code ec;
    fs::remove_all(d.temporary, ec);
  }
  committed_ = true;
}

}  // namespace keel::app
