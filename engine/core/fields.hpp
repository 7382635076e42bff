// A struct's members listed once, with their names. Inside a struct,
//
//   struct Outcome {
//     std::vector<int> selected;
//     double cost = 0.0;
//     KEEL_FIELDS(selected, cost)
//   };
//
// gives fields() (a std::tie of the members, const and non-const: what repro::save/load walk) and
// field_list() (the list as written, "selected, cost"); core::field_names<T>() splits it into names and
// core::for_each_field(x, f) calls f(name, member) for each member in order. The list is written once, so
// the archive, and every walk over a struct by name, cannot disagree about its members.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

#define KEEL_FIELDS(...)                                \
  auto fields() { return std::tie(__VA_ARGS__); }       \
  auto fields() const { return std::tie(__VA_ARGS__); } \
  static constexpr std::string_view field_list() { return #__VA_ARGS__; }

namespace keel::core {

template <class T>
concept NamedFields = requires(T& t) {
  t.fields();
  { T::field_list() } -> std::convertible_to<std::string_view>;
};

/// The member names of KEEL_FIELDS, in order.
template <NamedFields T>
constexpr auto field_names() {
  constexpr std::size_t n = std::tuple_size_v<decltype(std::declval<T&>().fields())>;
  constexpr std::string_view list = T::field_list();
  std::array<std::string_view, n> names{};
  std::size_t start = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (start < list.size() && (list[start] == ' ' || list[start] == ',')) ++start;
    std::size_t end = start;
    while (end < list.size() && list[end] != ',' && list[end] != ' ') ++end;
    names[k] = list.substr(start, end - start);
    start = end;
  }
  return names;
}

/// f(name, member) for each member of KEEL_FIELDS, in order (const or not as x is).
template <class T, class F>
  requires NamedFields<std::remove_const_t<T>>
void for_each_field(T& x, F&& f) {
  constexpr auto names = field_names<std::remove_const_t<T>>();
  auto members = x.fields();
  [&]<std::size_t... k>(std::index_sequence<k...>) {
    (f(names[k], std::get<k>(members)), ...);
  }(std::make_index_sequence<names.size()>{});
}

}  // namespace keel::core
