// Numbers in report prose come from the results, not from the keyboard: the `discussion` text of an
// experiment.toml names values by placeholders that the report fills in, so a number in the reading cannot
// disagree with the table beside it.
//
//   {metric:KEY}            metric KEY of this experiment's results
//   {timing:KEY}            timings_s KEY
//   {series:KEY[I]}         element I (0-based) of series KEY; also [min], [max], [mean], [median], [size]
//   {thesis:KEY}            [thesis.values] KEY of this experiment
//   {ID/metric:KEY} …       the same kinds from another experiment's results (ID = its folder name)
//
// Each takes an optional format after '|': .3g (default: 3 significant digits), .2f (fixed), .1% (a rate as a
// percentage, "94.1 %"), .2e (scientific), d (integer, thousands separated by thin spaces: "100 000").
// A literal '{' is written '{{'. An unknown kind, key, index or format is an error naming the placeholder and
// the nearest valid key.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace keel::repro {

// What a placeholder asks for: kind ("metric", "timing", "series", "thesis"), key, the series selector (empty
// unless kind is "series") and the experiment (empty: this one).
struct ProseRef {
  std::string experiment, kind, key, selector;
};

// Answers a placeholder, or nullopt if the key does not exist; `keys` lists the valid keys of a kind (for the
// error's suggestion).
struct ProseLookup {
  std::function<std::optional<double>(const ProseRef&)> value;
  std::function<std::vector<std::string>(const std::string& experiment, const std::string& kind)> keys;
  // Written for a placeholder whose key does not resolve, instead of an error (a quick-profile report: the
  // discussion names points only the full profile computes). Empty: an unresolved key is an error.
  std::string missing_text;
  // Written for a placeholder whose experiment has no results to read (a run of some experiments only, whose
  // discussion quotes one that was neither run nor blessed); returns empty where the results exist, so a key
  // missing from existing results stays an error. Unset: every unresolved key is an error.
  std::function<std::string(const ProseRef&)> unavailable;
};

// Replaces every placeholder of `text`. Throws std::invalid_argument "<where>: placeholder '{…}': <reason>".
[[nodiscard]] std::string expand_prose(std::string_view text, const ProseLookup& lookup,
                                       std::string_view where);

// The placeholders of `text` (for checks that every one resolves, without expanding).
[[nodiscard]] std::vector<ProseRef> prose_placeholders(std::string_view text, std::string_view where);

// Formats v by a placeholder format (see above). Throws std::invalid_argument for an unknown format.
[[nodiscard]] std::string format_prose_number(double v, std::string_view format);

// A number written literally in prose, outside placeholders: its text, its value and its byte offset.
struct LiteralNumber {
  std::string text;
  double value = 0;
  std::size_t offset = 0;
};

// The literal numbers of `text` that are not structural references: numbers after "Table", "Fig.", "Figs.",
// "eq.", "eqs.", "§", "chapter", "ch.", "Theorem" or "order" (a relaxation order); "(1)"-style equation tags;
// group and dimension names (SE(3), SO(2), 1D, 3D); and digits inside identifiers or `code` spans. Ranges
// "2–39" give two numbers.
[[nodiscard]] std::vector<LiteralNumber> literal_numbers(std::string_view text);

// Whether a literal is `value` as written to its own precision (0.941 matches 0.94074; "94 %" and "94" match
// 0.94 as a percentage; 8100 matches 8100 only).
[[nodiscard]] bool literal_matches(const LiteralNumber& literal, double value);

}  // namespace keel::repro
