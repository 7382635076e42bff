// The `keel` command's pieces, one file per subcommand: the reproduction commands (list.cpp, diff.cpp,
// bless.cpp, report.cpp, eta.cpp, prose_check.cpp, same.cpp) and the commands that run keel on a user's files
// (check.cpp, solve.cpp, marginals.cpp, pcm.cpp, split.cpp, align.cpp). Included after the importing file's
// `import`s (DESIGN rule 4).
#pragma once

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace keel::cli {

// Exit codes of every subcommand (documented in `keel --help`, each command's --help and docs/USING.md).
enum Exit : int {
  ok = 0,         // done
  failed = 1,     // done, but not what was asked: a solver failed, `--certify` not certified, results differ
  usage = 2,      // bad command line (an unknown option, an option value refused) or experiment config
  bad_input = 3,  // an input file that cannot be read or parsed, or values in it the engine refuses
  cannot_write = 4,  // an output that cannot be written or is refused (an input, or an existing file of
                     // another kind); nothing was written
};

// The table above as `keel --help` and each command's --help print it.
inline constexpr const char* kExitTable =
    "Exit status: 0 done; 1 done, but not what was asked (a solver failed, --certify not certified, results "
    "differ or leave their tolerance); 2 bad command line or experiment config (an unknown option, or an "
    "option value keel refuses, before any input is read); 3 an input that cannot be read or parsed, or "
    "values in it keel refuses; 4 an output that cannot be written, or is refused (one of the "
    "inputs, "
    "or an existing file of another kind). Outputs are written only on exit 0, each to a temporary file "
    "beside "
    "it renamed into place at the end: any other exit leaves every file as it was.";

// Thrown by a command whose work ran to completion with a negative answer (exit 1); the message is printed.
struct CommandFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Options every file command takes.
struct Common {
  bool quiet = false;  // no progress lines on stderr, no solver log
  bool json = false;   // machine-readable output on stdout
};

// "keel 0.1 (commit 0123456789ab)": the version and the commit the binary was built from (version.cpp).
const char* version_string();

// Reproduction ("Reproduction" group of --help).
void add_list_command(CLI::App& app);
void add_diff_command(CLI::App& app);
void add_bless_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_eta_command(CLI::App& app);
void add_prose_check_command(CLI::App& app);
void add_same_command(CLI::App& app);
// A user's files ("Your data" group).
void add_check_command(CLI::App& app);
void add_solve_command(CLI::App& app);
void add_marginals_command(CLI::App& app);
void add_pcm_command(CLI::App& app);
void add_robust_command(CLI::App& app);
void add_split_command(CLI::App& app);
void add_align_command(CLI::App& app);

}  // namespace keel::cli
