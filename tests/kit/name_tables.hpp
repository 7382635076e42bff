// One check for every enum <-> string name table (core/names.hpp, docs/DESIGN.md "Naming and errors"), used
// by engine/study/names_test.cpp over the tables of every area. Include it as "kit/name_tables.hpp".
#pragma once

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cctype>
#include <cstddef>
#include <initializer_list>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "kit/test_kit.hpp"

namespace keel::testkit {

// The valid names an "unknown <type> '<text>' (valid: a, b, c)" message lists, or {"<not that message>"}.
inline std::vector<std::string> listed_valid_names(const std::string& message, std::string_view type,
                                                   std::string_view text) {
  const std::string head = fmt::format("unknown {} '{}' (valid: ", type, text);
  if (message.rfind(head, 0) != 0 || message.size() < head.size() + 1 || message.back() != ')')
    return {"<not that message>"};
  std::vector<std::string> out;
  const std::string list = message.substr(head.size(), message.size() - head.size() - 1);
  for (std::size_t start = 0;;) {
    const std::size_t comma = list.find(", ", start);
    out.push_back(list.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 2;
  }
  return out;
}

inline bool is_snake_case(std::string_view s) {
  if (s.empty() || !std::islower(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s)
    if (!std::islower(static_cast<unsigned char>(c)) && !std::isdigit(static_cast<unsigned char>(c)) &&
        c != '_')
      return false;
  return true;
}

// Checks the name table of enum E named `type` (as its messages name it, e.g. "pgo::Method"), given every
// enumerator in declaration order and E's parse function `<e>_from_string`:
//   * the enumerators are 0, 1, …, n − 1 and to_string (found by ADL) names each one, in snake_case, and no
//     value past the last ("<type>: value n has no name"): the list and the table hold the same values;
//   * the names are unique, and each parses back to its enumerator;
//   * an unknown name, and a valid name in upper case (names match exactly), throw std::invalid_argument
//     "unknown <type> '<text>' (valid: …)" listing every valid name once.
// An enum whose area declares to_string only (no parse) passes `nullptr` as `parse`: the parse checks are
// left out.
template <class E, class Parse>
void check_name_table(std::string_view type, std::initializer_list<E> enumerators, Parse parse) {
  static_assert(std::is_enum_v<E>);
  const std::string type_name(type);
  INFO("name table of ", type_name);
  std::vector<std::string> names;
  long long expected = 0;
  for (E e : enumerators) {
    CHECK(static_cast<long long>(e) == expected);
    ++expected;
    const std::string name(to_string(e));
    CHECK_MESSAGE(is_snake_case(name), "'", name, "' is not snake_case");
    if constexpr (!std::is_null_pointer_v<Parse>) {
      CHECK_MESSAGE(parse(name) == e, "'", name, "' does not parse back to its enumerator");
    }
    names.push_back(name);
  }
  REQUIRE(!names.empty());
  const std::set<std::string> unique(names.begin(), names.end());
  CHECK_MESSAGE(unique.size() == names.size(), "duplicate names in ",
                fmt::format("{}", fmt::join(names, ", ")));
  CHECK(message_of([&] { (void)to_string(static_cast<E>(expected)); }) ==
        fmt::format("{}: value {} has no name", type, expected));
  if constexpr (!std::is_null_pointer_v<Parse>) {
    std::string upper = names.front();
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const std::string& text : {std::string("no_such_name"), std::string(), upper}) {
      const std::string message = message_of([&] { (void)parse(text); });
      const std::vector<std::string> listed = listed_valid_names(message, type, text);
      INFO("message: ", message);
      CHECK(listed.size() == names.size());
      CHECK(std::set<std::string>(listed.begin(), listed.end()) == unique);
    }
  }
}

}  // namespace keel::testkit
