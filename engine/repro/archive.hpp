// A binary archive for per-trial records: the partial files of sharded runs (core/shard.hpp) hold each
// trial's record as bytes written here and read back, value for value, when the shards are merged.
//
// What can be saved:
//   - trivially copyable types (arithmetic, enums, plain structs of them): their bytes;
//   - std::string, std::vector, std::array, std::pair, std::tuple, std::optional, std::map;
//   - dense matrices (Eigen, by duck typing: Scalar, rows(), cols(), data(), resize(r, c)): shape and
//   entries;
//   - any class whose members are listed by KEEL_FIELDS (core/fields.hpp: fields(), a std::tie of them):
//       struct Outcome { std::vector<int> selected; double cost = 0; KEEL_FIELDS(selected, cost) };
//     A member left out of the list is not carried to the merge; the N-shard tests compare merged and
//     single-machine results, so such an omission shows as a difference there.
// The byte order is the machine's (partials are merged on the cluster that wrote them); Reader refuses to
// read past the end of its bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace keel::repro {

class Writer {
 public:
  void bytes(const void* p, std::size_t n) {
    if (n > 0) buffer_.append(static_cast<const char*>(p), n);  // an empty vector's data() may be null
  }
  const std::string& buffer() const { return buffer_; }
  std::string take() { return std::move(buffer_); }

 private:
  std::string buffer_;
};

class Reader {
 public:
  explicit Reader(std::string_view data) : data_(data) {}
  void bytes(void* p, std::size_t n) {
    if (n == 0) return;  // an empty vector's data() may be null: no memcpy
    if (n > data_.size() - pos_)
      throw std::runtime_error(
          "partial record: read past the end (the file is truncated or of another layout)");
    std::memcpy(p, data_.data() + pos_, n);
    pos_ += n;
  }
  bool done() const { return pos_ == data_.size(); }
  std::size_t remaining() const { return data_.size() - pos_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
};

template <class T>
concept HasFields = requires(T& t, const T& c) {
  t.fields();
  c.fields();
};

template <class T>
concept DenseMatrix = requires(T& m) {
  typename T::Scalar;
  m.rows();
  m.cols();
  m.data();
  m.resize(0, 0);
};

template <class T>
void save(Writer& w, const T& v);
template <class T>
void load(Reader& r, T& v);

namespace archive_detail {

inline void save_size(Writer& w, std::size_t n) {
  const auto u = static_cast<std::uint64_t>(n);
  w.bytes(&u, sizeof u);
}
inline std::size_t load_size(Reader& r) {
  std::uint64_t u = 0;
  r.bytes(&u, sizeof u);
  if (u > r.remaining() && u > (std::uint64_t{1} << 40))
    throw std::runtime_error("partial record: implausible element count (corrupt file)");
  return static_cast<std::size_t>(u);
}

template <class T>
struct is_vector : std::false_type {};
template <class T, class A>
struct is_vector<std::vector<T, A>> : std::true_type {};
template <class T>
struct is_array : std::false_type {};
template <class T, std::size_t N>
struct is_array<std::array<T, N>> : std::true_type {};
template <class T>
struct is_pair : std::false_type {};
template <class A, class B>
struct is_pair<std::pair<A, B>> : std::true_type {};
template <class T>
struct is_tuple : std::false_type {};
template <class... Ts>
struct is_tuple<std::tuple<Ts...>> : std::true_type {};
template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};
template <class T>
struct is_map : std::false_type {};
template <class K, class V, class C, class A>
struct is_map<std::map<K, V, C, A>> : std::true_type {};

}  // namespace archive_detail

template <class T>
void save(Writer& w, const T& v) {
  using namespace archive_detail;
  if constexpr (std::is_same_v<T, std::string>) {
    save_size(w, v.size());
    w.bytes(v.data(), v.size());
  } else if constexpr (std::is_same_v<T, std::vector<bool>>) {
    save_size(w, v.size());
    for (bool b : v) save(w, static_cast<std::uint8_t>(b));
  } else if constexpr (is_vector<T>::value) {
    save_size(w, v.size());
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) {
      w.bytes(v.data(), v.size() * sizeof(typename T::value_type));
    } else {
      for (const auto& x : v) save(w, x);
    }
  } else if constexpr (is_array<T>::value) {
    for (const auto& x : v) save(w, x);
  } else if constexpr (is_pair<T>::value) {
    save(w, v.first);
    save(w, v.second);
  } else if constexpr (is_tuple<T>::value) {
    std::apply([&](const auto&... x) { (save(w, x), ...); }, v);
  } else if constexpr (is_optional<T>::value) {
    save(w, static_cast<std::uint8_t>(v.has_value()));
    if (v) save(w, *v);
  } else if constexpr (is_map<T>::value) {
    save_size(w, v.size());
    for (const auto& [k, x] : v) {
      save(w, k);
      save(w, x);
    }
  } else if constexpr (HasFields<T>) {
    std::apply([&](const auto&... x) { (save(w, x), ...); }, v.fields());
  } else if constexpr (DenseMatrix<T>) {
    save_size(w, static_cast<std::size_t>(v.rows()));
    save_size(w, static_cast<std::size_t>(v.cols()));
    w.bytes(v.data(), static_cast<std::size_t>(v.rows() * v.cols()) * sizeof(typename T::Scalar));
  } else {
    static_assert(std::is_trivially_copyable_v<T>,
                  "repro::save: list this type's members with KEEL_FIELDS (core/fields.hpp)");
    w.bytes(&v, sizeof v);
  }
}

template <class T>
void load(Reader& r, T& v) {
  using namespace archive_detail;
  if constexpr (std::is_same_v<T, std::string>) {
    v.resize(load_size(r));
    r.bytes(v.data(), v.size());
  } else if constexpr (std::is_same_v<T, std::vector<bool>>) {
    v.resize(load_size(r));
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::uint8_t b = 0;
      load(r, b);
      v[i] = b != 0;
    }
  } else if constexpr (is_vector<T>::value) {
    const std::size_t n = load_size(r);
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) {
      v.resize(n);
      r.bytes(v.data(), n * sizeof(typename T::value_type));
    } else {
      v.clear();
      v.resize(n);
      for (auto& x : v) load(r, x);
    }
  } else if constexpr (is_array<T>::value) {
    for (auto& x : v) load(r, x);
  } else if constexpr (is_pair<T>::value) {
    load(r, v.first);
    load(r, v.second);
  } else if constexpr (is_tuple<T>::value) {
    std::apply([&](auto&... x) { (load(r, x), ...); }, v);
  } else if constexpr (is_optional<T>::value) {
    std::uint8_t has = 0;
    load(r, has);
    if (has) {
      v.emplace();
      load(r, *v);
    } else {
      v.reset();
    }
  } else if constexpr (is_map<T>::value) {
    v.clear();
    const std::size_t n = load_size(r);
    for (std::size_t i = 0; i < n; ++i) {
      typename T::key_type k{};
      typename T::mapped_type x{};
      load(r, k);
      load(r, x);
      v.emplace(std::move(k), std::move(x));
    }
  } else if constexpr (HasFields<T>) {
    std::apply([&](auto&... x) { (load(r, x), ...); }, v.fields());
  } else if constexpr (DenseMatrix<T>) {
    const auto rows = static_cast<long>(load_size(r)), cols = static_cast<long>(load_size(r));
    v.resize(rows, cols);
    r.bytes(v.data(), static_cast<std::size_t>(rows * cols) * sizeof(typename T::Scalar));
  } else {
    static_assert(std::is_trivially_copyable_v<T>,
                  "repro::load: list this type's members with KEEL_FIELDS (core/fields.hpp)");
    r.bytes(&v, sizeof v);
  }
}

}  // namespace keel::repro
