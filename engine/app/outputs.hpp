// keel::app — the output files of one command, written all or nothing. Every output is checked before the
// work starts and written to a temporary file beside it; the temporaries are renamed into place only when
// the whole command succeeded, so a failing run leaves every existing file as it was.
//
// The rules, checked when an output is reserved (before any computation):
//  - an output is never one of the command's inputs (the same file by any path: std::filesystem::equivalent),
//    and two outputs never share a path;
//  - an existing file is replaced only when it holds what the command writes there (OutputKind): a JSON
//    document for a JSON output, a pose graph for a graph output; the files of a folder output (keel split,
//    keel align-world) only when the folder holds the complete set an earlier run of that command wrote, each
//    recognized by its first line; anything else at an output path (another kind of file, a folder, a
//    device) is refused;
//  - the output's folder must exist (a folder output's folder is created) and be writable: the temporary file
//    is created there at once, so an unwritable path fails with the system's reason before the work; an
//    existing file must be writable too, and its replacement keeps its permissions.
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace keel::app {

/// An output that cannot or may not be written (the `keel` command exits 4). The message names the path
/// and the reason ("m.json: cannot write: Permission denied").
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What an output file holds; an existing file at its path is replaced only when it holds the same (an empty
/// file is always replaced).
struct OutputKind {
  enum class Type { json, graph, first_line };
  Type type = Type::json;
  std::string first_line;  // Type::first_line: the file's first line starts with this

  static OutputKind json() { return {Type::json, {}}; }
  static OutputKind graph() { return {Type::graph, {}}; }
  static OutputKind starting_with(std::string prefix) { return {Type::first_line, std::move(prefix)}; }
  /// "a JSON document", "a pose graph (g2o or iSAM)", "a file whose first line starts with 'x,y'".
  [[nodiscard]] std::string describe() const;
  /// Whether the head (first bytes) of an existing file is of this kind.
  [[nodiscard]] bool matches(std::string_view head, const std::filesystem::path& file) const;
};

/// One file of a folder output.
struct FolderFile {
  std::string name;
  OutputKind kind;
};
/// The files keel split (app::split_files) writes: a.g2o, b.g2o, candidates.g2o, labels.txt, truth.txt.
[[nodiscard]] std::vector<FolderFile> split_folder_files();
/// The files keel split --robots N (app::robot_files) writes: robot0.g2o … robot<N−1>.g2o, candidates.g2o
/// (N ≥ 2) and closures.txt.
[[nodiscard]] std::vector<FolderFile> robot_folder_files(int robots);
/// The files keel align-world (app::write_alignment_world, write_terrain_world) writes: reference.csv,
/// query.csv, truth.csv.
[[nodiscard]] std::vector<FolderFile> world_folder_files();

/// Checks, before a command's work, that files can be created in folder `dir` (or, when it does not exist
/// yet, in its nearest existing ancestor, where it will be created) by creating and removing a temporary file
/// there; for commands that write through their own atomic writer (keel report, keel bless). Throws
/// OutputError "dir: cannot write: reason" naming `name`.
void check_folder_writable(const std::string& name, const std::filesystem::path& dir);

/// From now on, SIGINT, SIGTERM and SIGHUP first remove every temporary of a live Outputs (and the folders it
/// created, when still empty), then end the process as the signal would. For programs that own their signals
/// (the `keel` command); a host such as Python keeps its own handlers by not calling this.
void remove_temporaries_on_signals();

/// The outputs of one command. Reserve each output (file() or folder()) before the work, write to the
/// temporary path returned (write() turns a writer's failure into OutputError), then commit(). Destroyed
/// without commit() (the command failed), it removes its temporary files and the folders it created.
class Outputs {
 public:
  /// The command's inputs as (name, path), e.g. {"--a", "a.g2o"}; an input that does not exist is skipped
  /// (reading it reports the error).
  explicit Outputs(std::vector<std::pair<std::string, std::filesystem::path>> inputs = {});
  ~Outputs();
  Outputs(const Outputs&) = delete;
  Outputs& operator=(const Outputs&) = delete;

  /// Reserves the output `target` named `name` (e.g. "--out"): checks it (the rules above) and creates its
  /// temporary file beside it, with target's extension; returns that temporary path. Throws OutputError.
  std::filesystem::path file(const std::string& name, const std::filesystem::path& target, OutputKind kind);
  /// Reserves the files of a folder output: checks each as file() does (and the complete-set rule), creates
  /// `dir` when missing and a temporary folder inside it; returns that folder, where the command writes the
  /// files under their names. Throws OutputError.
  std::filesystem::path folder(const std::string& name, const std::filesystem::path& dir,
                               const std::vector<FolderFile>& files);
  /// Runs writer(temporary) for a reserved file output; an exception becomes OutputError naming target.
  void write(const std::filesystem::path& target,
             const std::function<void(const std::filesystem::path& temporary)>& writer);
  /// Writes text to a reserved file output. Throws OutputError with the system's reason.
  void write_text(const std::filesystem::path& target, std::string_view text);
  /// Renames every temporary into place (the files of a folder output too, then removes the temporary
  /// folder). Throws OutputError naming the file that could not be renamed, std::logic_error for a file
  /// output that write() or write_text() never wrote.
  void commit();

 private:
  struct File {
    std::filesystem::path target, temporary;
    bool written = false;  // by write() or write_text(); commit() refuses to rename an unwritten temporary
    std::filesystem::perms mode = std::filesystem::perms::unknown;  // an existing target's, kept by commit()
  };
  struct Folder {
    std::filesystem::path dir, temporary;
    std::vector<std::string> names;
  };
  void check_target(const std::string& name, const std::filesystem::path& target, const OutputKind& kind,
                    bool folder_member);
  File& reserved(const std::filesystem::path& target);

  std::vector<std::pair<std::string, std::filesystem::path>> inputs_;
  std::vector<std::pair<std::string, std::filesystem::path>> claimed_;  // (name, absolute path) of outputs
  std::vector<File> files_;
  std::vector<Folder> folders_;
  std::vector<std::filesystem::path> created_dirs_;  // removed again (when empty) if the command fails
  std::vector<int> signal_slots_;  // this object's entries for remove_temporaries_on_signals
  bool committed_ = false;
};

}  // namespace keel::app
