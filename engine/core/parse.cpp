#include "core/parse.hpp"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <system_error>

namespace keel::core {

namespace {

// Drops one leading '+' that from_chars does not take ("+-1" and "++1" keep theirs and are refused).
std::string_view without_plus(std::string_view s) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  return s;
}

}  // namespace

std::string quote_token(std::string_view token) {
  std::string out = "'";
  std::size_t n = 0;
  for (char ch : token) {
    if (n++ == 40) {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f && c != '\\' && c != '\'') {
      out += ch;
    } else {
      fmt::format_to(std::back_inserter(out), "\\x{:02x}", c);
    }
  }
  out += "'";
  return out;
}

std::string parse_integer(std::string_view token, std::int64_t lo, std::int64_t hi, std::int64_t& out,
                          std::string_view expected) {
  const std::string_view s = without_plus(token);
  std::int64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 10);
  const bool whole = p == s.data() + s.size() && !s.empty();
  if (ec != std::errc() && !(ec == std::errc::result_out_of_range && whole)) {
    return fmt::format("{} is not {} (expected a decimal integer in {} … {})", quote_token(token), expected,
                       lo, hi);
  }
  if (!whole) {
    return fmt::format("{} is not {} (expected a decimal integer in {} … {})", quote_token(token), expected,
                       lo, hi);
  }
  const bool negative = !s.empty() && s[0] == '-';
  const bool small = ec == std::errc::result_out_of_range ? negative : v < lo;
  if (ec == std::errc::result_out_of_range || v < lo || v > hi) {
    if (negative && lo == 0) {
      return fmt::format("{} is negative: expected {} in 0 … {}", quote_token(token), expected, hi);
    }
    return fmt::format("{} is too {}: expected {} in {} … {}", quote_token(token), small ? "small" : "large",
                       expected, lo, hi);
  }
  out = v;
  return {};
}

std::string parse_real(std::string_view token, double& out) {
  const std::string_view s = without_plus(token);
  double v = 0.0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
  const bool whole = p == s.data() + s.size() && !s.empty();
  if (!whole || (ec != std::errc() && ec != std::errc::result_out_of_range)) {
    return fmt::format("{} is not a number (expected a finite decimal real such as -2.5e-3)",
                       quote_token(token));
  }
  if (ec == std::errc::result_out_of_range) {
    // The token is a well-formed decimal whose value lies outside the normal doubles: strtod tells an
    // underflow (a subnormal, or ±0 below the smallest subnormal: the correctly rounded value) from an
    // overflow.
    const std::string copy(s);
    v = std::strtod(copy.c_str(), nullptr);
  }
  if (!std::isfinite(v)) {
    const bool spelled = s.find_first_of("iInN") != std::string_view::npos;  // "inf", "nan", not "1e999"
    if (spelled)
      return fmt::format("{} is not a finite number (NaN and infinities are refused)", quote_token(token));
    return fmt::format("{} is out of the range of a double (a finite real of magnitude at most 1.797e308)",
                       quote_token(token));
  }
  out = v;
  return {};
}

std::int64_t to_integer(std::string_view token, std::int64_t lo, std::int64_t hi, std::string_view what,
                        std::string_view expected) {
  std::int64_t v = 0;
  if (auto why = parse_integer(token, lo, hi, v, expected); !why.empty())
    throw std::invalid_argument(fmt::format("{}: {}", what, why));
  return v;
}

double to_real(std::string_view token, std::string_view what) {
  double v = 0.0;
  if (auto why = parse_real(token, v); !why.empty())
    throw std::invalid_argument(fmt::format("{}: {}", what, why));
  return v;
}

std::string parse_id_range(std::string_view token, std::int64_t limit, IdRange& out,
                           std::string_view expected) {
  if (limit <= 0)
    return fmt::format("{}: there is no {} to choose (none exists)", quote_token(token), expected);
  // The dash of a range is the first '-' after the first character (a leading '-' is a sign, refused below).
  const std::size_t dash = token.find('-', 1);
  std::int64_t a = 0, b = 0;
  if (dash == std::string_view::npos) {
    if (auto why = parse_integer(token, 0, limit - 1, a, expected); !why.empty()) return why;
    out = {a, a};
    return {};
  }
  if (auto why = parse_integer(token.substr(0, dash), 0, limit - 1, a, expected); !why.empty())
    return fmt::format("range {}: {}", quote_token(token), why);
  if (auto why = parse_integer(token.substr(dash + 1), 0, limit - 1, b, expected); !why.empty())
    return fmt::format("range {}: {}", quote_token(token), why);
  if (b < a) return fmt::format("range {}: the end {} is below the start {}", quote_token(token), b, a);
  out = {a, b};
  return {};
}

std::vector<int> parse_id_list(std::string_view spec, std::int64_t limit, std::int64_t max_count,
                               std::string_view what, std::string_view expected) {
  std::vector<IdRange> ranges;
  std::int64_t total = 0;
  for (const std::string_view item : split_fields(spec, ',')) {
    IdRange r;
    if (auto why = parse_id_range(item, limit, r, expected); !why.empty())
      throw std::invalid_argument(fmt::format("{}: {}", what, why));
    total += r.count();  // each count <= limit, and there are at most spec.size() ranges: no overflow
    if (total > max_count) {
      throw std::invalid_argument(fmt::format(
          "{}: '{}' names more than {} ids (the list is checked before it is expanded)", what,
          spec.size() > 40 ? std::string(spec.substr(0, 40)) + "..." : std::string(spec), max_count));
    }
    ranges.push_back(r);
  }
  std::vector<int> out;
  out.reserve(static_cast<std::size_t>(total));
  for (const auto& r : ranges)
    for (std::int64_t k = r.first; k <= r.last; ++k) out.push_back(static_cast<int>(k));
  return out;
}

bool is_header_field(std::string_view f) {
  if (!f.empty() && f.front() == '"') f.remove_prefix(1);
  if (f.empty()) return false;
  const auto c = static_cast<unsigned char>(f.front());
  const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
  if (!letter) return false;
  std::string lower(f);
  for (char& ch : lower)
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
  while (!lower.empty() && lower.back() == '"') lower.pop_back();
  return lower != "nan" && lower != "inf" && lower != "infinity" && lower.rfind("nan(", 0) != 0;
}

NumericCsv parse_numeric_csv(std::string_view text, const std::string& name, std::size_t min_columns,
                             std::string_view need) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a UTF-8 byte-order mark
  NumericCsv t;
  int number = 0;
  bool first_record = true;
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  for (const std::string_view line : split_fields(text, '\n')) {
    ++number;
    std::size_t b = 0;
    while (b < line.size() && blank(line[b])) ++b;
    if (b == line.size() || line[b] == '#') continue;
    std::vector<std::string_view> f = split_fields(line, ',');
    for (auto& x : f) {
      while (!x.empty() && blank(x.front())) x.remove_prefix(1);
      while (!x.empty() && blank(x.back())) x.remove_suffix(1);
    }
    if (first_record) {
      first_record = false;
      bool header = true;
      for (const auto& x : f) header = header && is_header_field(x);
      if (header) {
        t.header = true;
        continue;
      }
    }
    if (t.columns == 0) {
      if (f.size() < min_columns)
        throw std::invalid_argument(fmt::format("{}:{}: {} columns; need {}", name, number, f.size(), need));
      t.columns = f.size();
    }
    if (f.size() != t.columns) {
      throw std::invalid_argument(
          fmt::format("{}:{}: {} columns where the first record has {}", name, number, f.size(), t.columns));
    }
    for (std::size_t k = 0; k < f.size(); ++k) {
      double v = 0.0;
      if (auto why = parse_real(f[k], v); !why.empty())
        throw std::invalid_argument(fmt::format("{}:{}: column {}: {}", name, number, k + 1, why));
      t.values.push_back(v);
    }
    t.lines.push_back(number);
  }
  return t;
}

std::string read_whole_file(const std::filesystem::path& file, std::string& text) {
  text.clear();
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fmt::format("cannot open file ({})", std::strerror(errno));
  struct stat st{};
  if (::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    ::close(fd);
    return "cannot read: is a directory, not a file";
  }
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      text.clear();
      return e == EISDIR ? std::string("cannot read: is a directory, not a file")
                         : fmt::format("read error: {}", std::strerror(e));
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return {};
}

std::string read_text_file(const std::filesystem::path& file) {
  std::string text;
  if (auto why = read_whole_file(file, text); !why.empty())
    throw std::invalid_argument(fmt::format("{}: {}", file.string(), why));
  return text;
}

std::vector<std::string_view> split_fields(std::string_view text, char sep) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(sep, start);
    if (end == std::string_view::npos) {
      out.push_back(text.substr(start));
      return out;
    }
    out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
}

}  // namespace keel::core
