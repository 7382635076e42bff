// keel — one command for the reproduction machinery (list, diff, bless, report, eta, prose-check, same) and
// for running keel on a researcher's own files (check, solve, marginals, pcm, split, align); one file per
// subcommand (commands.hpp). docs/USING.md has a worked example of each. Exit codes: see Exit in
// commands.hpp.
import keel.core;
import keel.app;
import keel.datasets;
import keel.graph;

#include <fmt/format.h>

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

#include "commands.hpp"

namespace {

// Prints "keel <command>: <message>" and returns the exit code of the error's class (Exit in commands.hpp). A
// message that begins with the command's own name ("robust: …", from merge::robust) is printed once, not as
// "keel robust: robust: …".
int report_error(const char* command, std::exception_ptr error) {
  using namespace keel::cli;
  auto say = [&](const std::string& prefix, const std::exception& e, int code) {
    std::string_view message = e.what();
    const std::string own = std::string(command) + ": ";
    if (prefix.empty() && message.starts_with(own)) message.remove_prefix(own.size());
    fmt::print(stderr, "keel {}: {}{}\n", command, prefix, message);
    return code;
  };
  try {
    std::rethrow_exception(error);
  } catch (const CommandFailed& e) {
    return say("", e, Exit::failed);
  } catch (const keel::app::OutputError& e) {  // an output refused or not writable; nothing was written
    return say("", e, Exit::cannot_write);
  } catch (const keel::core::ConfigError& e) {
    return say("config error: ", e, Exit::usage);
  } catch (const keel::graph::ParseError& e) {  // file, line, field
    return say("", e, Exit::bad_input);
  } catch (const keel::datasets::DatasetError& e) {  // a data-set file missing or not verified
    return say("", e, Exit::bad_input);
  } catch (const std::filesystem::filesystem_error& e) {
    return say("", e, Exit::bad_input);
  } catch (const std::logic_error& e) {  // invalid_argument, out_of_range: values the engine refuses
    return say("", e, Exit::bad_input);
  } catch (const std::exception& e) {  // a solver or factorization that failed
    return say("", e, Exit::failed);
  }
}

// Every number on the command line goes through the one parser (core::parse_integer, core::parse_real)
// before CLI11 converts it: a value out of range of its type (overflow, a negative for an unsigned option),
// trailing junk, inf or nan is a usage error (exit 2) naming the option, never a wrapped or clamped value.
// CLI11 names an option's C++ type INT (signed), UINT (unsigned) or FLOAT; its own conversion then refuses a
// value that does not fit a narrower type (int, unsigned).
CLI::Validator number_check(const std::string& type) {
  return CLI::Validator(
      [type](std::string& token) -> std::string {
        if (type == "FLOAT") {
          double v = 0.0;
          return keel::core::parse_real(token, v);
        }
        std::int64_t v = 0;
        if (type == "INT")
          return keel::core::parse_integer(token, std::numeric_limits<std::int64_t>::min(),
                                           std::numeric_limits<std::int64_t>::max(), v);
        // UINT: 0 … 2^64 − 1; the parser's range is that of int64, so the upper half is read apart.
        auto why = keel::core::parse_integer(token, 0, std::numeric_limits<std::int64_t>::max(), v);
        if (why.empty()) return why;
        std::uint64_t u = 0;
        const std::string_view s =
            !token.empty() && token[0] == '+' ? std::string_view(token).substr(1) : token;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), u, 10);
        if (!s.empty() && s[0] != '-' && ec == std::errc() && end == s.data() + s.size()) return {};
        const std::string int64_max = std::to_string(std::numeric_limits<std::int64_t>::max());
        if (const auto at = why.find(int64_max); at != std::string::npos)
          why.replace(at, int64_max.size(), std::to_string(std::numeric_limits<std::uint64_t>::max()));
        return why;
      },
      "", type == "FLOAT" ? "real" : "integer");
}

// Adds number_check to every numeric option of `app` and its subcommands.
void check_numbers(CLI::App& app) {
  for (auto* option : app.get_options()) {
    const std::string type = option->get_type_name();
    if (type == "INT" || type == "UINT" || type == "FLOAT") option->check(number_check(type));
  }
  for (auto* sub : app.get_subcommands({})) check_numbers(*sub);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace keel::cli;
  keel::app::remove_temporaries_on_signals();  // Ctrl-C during a command leaves no temporary output behind
  CLI::App app{"keel — robust multi-agent SLAM (reproduction of Mangelson 2019, and tools for your own data)",
               "keel"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_string(),
                       "print keel's version and the commit it was built from");
  app.footer(fmt::format("Each command has --help. {} Worked examples: docs/USING.md.", kExitTable));
  for (auto add :
       {add_list_command, add_diff_command, add_bless_command, add_report_command, add_eta_command,
        add_prose_check_command, add_same_command, add_check_command, add_solve_command,
        add_marginals_command, add_pcm_command, add_robust_command, add_split_command, add_align_command})
    add(app);
  for (auto* sub : app.get_subcommands({})) sub->footer(kExitTable);
  check_numbers(app);
  const char* command = argc > 1 ? argv[1] : "keel";
  try {
    app.parse(argc, argv);
    return Exit::ok;
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? Exit::ok : Exit::usage;
  } catch (...) {
    return report_error(command, std::current_exception());
  }
}
