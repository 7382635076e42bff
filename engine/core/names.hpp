// One enum <-> string convention for the whole engine (docs/DESIGN.md, "Naming and errors").
//
// Every public enum E of an area has exactly one name table, written once in the area's .cpp:
//
//     constexpr keel::core::NameTable<Method, 2> kMethodNames{"pgo::Method", {{
//         {Method::levenberg_marquardt, "levenberg_marquardt"},
//         {Method::dogleg, "dogleg"},
//     }}};
//     std::string_view to_string(Method v) { return kMethodNames.name(v); }
//     Method method_from_string(std::string_view s) { return kMethodNames.parse(s); }
//
// so the header declares `std::string_view to_string(E)` and `E <e>_from_string(std::string_view)`; the parse
// throws std::invalid_argument naming the type, the text and every valid name. Config readers add the
// location (ConfigTable::parse). Free of third-party includes, so any area's header may include it; the
// messages are built in names.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

namespace keel::core {

// std::invalid_argument "unknown <type> '<text>' (valid: a, b, c)".
[[noreturn]] void throw_unknown_name(std::string_view type, std::string_view text,
                                     const std::string_view* valid, std::size_t count);
// std::invalid_argument "<type>: value <value> has no name".
[[noreturn]] void throw_unnamed_value(std::string_view type, long long value);

template <class E, std::size_t N>
struct NameTable {
  std::string_view type;                                // e.g. "pgo::Method", used in error messages
  std::array<std::pair<E, std::string_view>, N> names;  // every enumerator exactly once

  // The name of `value`; throws std::invalid_argument for a value outside the table (a corrupted enum).
  constexpr std::string_view name(E value) const {
    for (const auto& [e, s] : names)
      if (e == value) return s;
    throw_unnamed_value(type, static_cast<long long>(value));
  }

  // The enumerator named `text` (exact match); throws std::invalid_argument naming every valid name.
  E parse(std::string_view text) const {
    std::array<std::string_view, N> valid{};
    for (std::size_t k = 0; k < N; ++k) {
      if (names[k].second == text) return names[k].first;
      valid[k] = names[k].second;
    }
    throw_unknown_name(type, text, valid.data(), N);
  }
};

}  // namespace keel::core
