// keel::core — the one parser of every integer and real number that keel reads from a command line or a file
// (graph ids, pose pairs and ranges, survey CSV fields, terrain grids). Built on std::from_chars, so it
// neither depends on the locale nor skips blanks:
//   integers  an optional sign and decimal digits, nothing else ("1e3", "0x10", " 1", "1 " are refused),
//   within
//             the caller's [lo, hi] (overflow of 64 bits is "out of range", never a wrapped value);
//   reals     the decimal forms of strtod ("1", "-2.5e-3", "+.5", "1e-310": subnormals are accepted, and a
//   value
//             below the smallest subnormal rounds to ±0 as IEEE 754 rounds any decimal); refused: inf, nan,
//             hexadecimal, a magnitude beyond the largest double ("1e309"), trailing junk;
//   ranges    "a" or "a-b" (inclusive) of ids in [0, limit), checked before anything is allocated.
// The parse_* forms return why a token is refused (empty when accepted); the messages quote the token and say
// what was expected, and the callers prefix them with the file, line and field or the option's name.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace keel::core {

/// The token as it appears in a message: quoted, at most 40 characters, non-printable bytes as \xNN.
[[nodiscard]] std::string quote_token(std::string_view token);

/// Why `token` is not a decimal integer in [lo, hi] (empty when it is; `out` then holds it). `expected` names
/// what the caller wanted ("a pose id"); it appears in the message.
[[nodiscard]] std::string parse_integer(std::string_view token, std::int64_t lo, std::int64_t hi,
                                        std::int64_t& out, std::string_view expected = "an integer");

/// Why `token` is not a finite real (empty when it is; `out` then holds it).
[[nodiscard]] std::string parse_real(std::string_view token, double& out);

/// Throwing forms: std::invalid_argument("{what}: {why}").
[[nodiscard]] std::int64_t to_integer(std::string_view token, std::int64_t lo, std::int64_t hi,
                                      std::string_view what, std::string_view expected = "an integer");
[[nodiscard]] double to_real(std::string_view token, std::string_view what);

/// An inclusive range of ids.
struct IdRange {
  std::int64_t first = 0, last = 0;
  [[nodiscard]] std::int64_t count() const { return last - first + 1; }
};

/// Why `token` is not an id "a" or a range "a-b" (a <= b) of ids in [0, limit) (empty when it is).
[[nodiscard]] std::string parse_id_range(std::string_view token, std::int64_t limit, IdRange& out,
                                         std::string_view expected = "an id");

/// A comma-separated list of ids and ranges ("0,5,10-20"), every id in [0, limit) and at most `max_count` ids
/// in all, both checked before the list is expanded. Throws std::invalid_argument("{what}: {why}").
[[nodiscard]] std::vector<int> parse_id_list(std::string_view spec, std::int64_t limit,
                                             std::int64_t max_count, std::string_view what,
                                             std::string_view expected = "an id");

/// A table of numbers read from CSV text (core::parse_numeric_csv).
struct NumericCsv {
  std::size_t columns = 0;
  std::vector<double> values;  // row-major, rows × columns
  std::vector<int> lines;      // the 1-based source line of each row
  bool header = false;         // the first record was a header (see the rule below)
  [[nodiscard]] std::size_t rows() const { return lines.size(); }
};

/// Whether a CSV field is a column name: it begins with a letter or '_' (after an optional '"') and spells no
/// NaN or infinity ("nan", "inf", "infinity", "nan(...)", any case).
[[nodiscard]] bool is_header_field(std::string_view field);

/// CSV text of numbers: a UTF-8 byte-order mark is dropped; blank lines and lines whose first non-blank is
/// '#' are skipped; fields are split at ',' and trimmed of blanks and CR. The header rule: only the first
/// record can be a header, and it is one exactly when every field is_header_field; every other record is
/// data, each field through parse_real. Every row has the first row's column count, at least `min_columns`
/// (`need` says what they are). Throws std::invalid_argument "name:line: column k: why", "name:line: n
/// columns where the first record has m" or "name:line: n columns; need {need}". An empty table is not an
/// error here.
[[nodiscard]] NumericCsv parse_numeric_csv(std::string_view text, const std::string& name,
                                           std::size_t min_columns, std::string_view need);

/// Reads a whole file in one pass (so a pipe, a FIFO or `<(cmd)` works: nothing is read twice): empty on
/// success, else the reason ("No such file or directory", "is a directory", "Permission denied", "read error:
/// ...").
[[nodiscard]] std::string read_whole_file(const std::filesystem::path& file, std::string& text);
/// The throwing form: std::invalid_argument("{file}: {reason}").
[[nodiscard]] std::string read_text_file(const std::filesystem::path& file);

/// Splits at `sep` (every field kept, empty ones too).
[[nodiscard]] std::vector<std::string_view> split_fields(std::string_view text, char sep);

}  // namespace keel::core
