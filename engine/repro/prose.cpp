#include "repro/prose.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace keel::repro {

namespace {

constexpr std::string_view kKinds[] = {"metric", "timing", "series", "thesis"};

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string nearest(const std::string& key, const std::vector<std::string>& keys) {
  std::string best;
  std::size_t d = std::string::npos;
  for (const auto& k : keys) {
    const std::size_t e = edit_distance(key, k);
    if (e < d) d = e, best = k;
  }
  return best;
}

// Parses the inside of one placeholder "ID/kind:key[sel]|fmt" into ref and format.
void parse_placeholder(std::string_view body, ProseRef& ref, std::string& format, std::string_view where,
                       std::string_view whole) {
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument(fmt::format("{}: placeholder '{}': {}", where, whole, why));
  };
  std::string_view spec = body;
  if (const auto bar = body.find('|'); bar != std::string_view::npos) {
    format = std::string(body.substr(bar + 1));
    spec = body.substr(0, bar);
  }
  const auto colon = spec.find(':');
  if (colon == std::string_view::npos) fail("expected kind:key (kinds: metric, timing, series, thesis)");
  std::string_view kind = spec.substr(0, colon), key = spec.substr(colon + 1);
  if (const auto slash = kind.find('/'); slash != std::string_view::npos) {
    ref.experiment = std::string(kind.substr(0, slash));
    kind = kind.substr(slash + 1);
    if (ref.experiment.empty()) fail("empty experiment id before '/'");
  }
  ref.kind = std::string(kind);
  if (std::find(std::begin(kKinds), std::end(kKinds), kind) == std::end(kKinds))
    fail(fmt::format("unknown kind '{}' (kinds: metric, timing, series, thesis)", kind));
  if (!ref.experiment.empty() && ref.kind == "thesis")
    fail("thesis values are read from this experiment only");
  if (ref.kind == "series") {
    const auto open = key.find('[');
    if (open == std::string_view::npos || key.back() != ']')
      fail("a series needs a selector: KEY[index], KEY[min], [max], [mean], [median] or [size]");
    ref.selector = std::string(key.substr(open + 1, key.size() - open - 2));
    key = key.substr(0, open);
    const bool number = !ref.selector.empty() && std::all_of(ref.selector.begin(), ref.selector.end(),
                                                             [](char c) { return std::isdigit(c) != 0; });
    if (!number && ref.selector != "min" && ref.selector != "max" && ref.selector != "mean" &&
        ref.selector != "median" && ref.selector != "size")
      fail(fmt::format("unknown series selector '[{}]' (an index, min, max, mean, median or size)",
                       ref.selector));
  }
  ref.key = std::string(key);
  if (ref.key.empty()) fail("empty key");
}

// Calls fn(body, whole, begin, end) for each placeholder; appends the literal text between them to `out` when
// out is not null. "{{" is a literal '{'.
template <class Fn>
void scan(std::string_view text, std::string_view where, std::string* out, Fn&& fn) {
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '{' && i + 1 < text.size() && text[i + 1] == '{') {
      if (out) *out += '{';
      i += 2;
      continue;
    }
    if (c != '{') {
      if (out) *out += c;
      ++i;
      continue;
    }
    const auto close = text.find('}', i);
    if (close == std::string_view::npos)
      throw std::invalid_argument(
          fmt::format("{}: unclosed placeholder at '{}' (write '{{{{' for a literal brace)", where,
                      text.substr(i, std::min<std::size_t>(30, text.size() - i))));
    fn(text.substr(i + 1, close - i - 1), text.substr(i, close - i + 1));
    i = close + 1;
  }
}

}  // namespace

std::string format_prose_number(double v, std::string_view format) {
  const std::string f = format.empty() ? std::string(".3g") : std::string(format);
  if (!std::isfinite(v)) return std::isnan(v) ? "NaN" : (v > 0 ? "∞" : "−∞");
  if (f == "d") {
    const long long n = std::llround(v);
    std::string digits = std::to_string(n < 0 ? -n : n), grouped;
    for (std::size_t k = 0; k < digits.size(); ++k) {
      if (k > 0 && (digits.size() - k) % 3 == 0 && digits.size() > 4) grouped += "\u2009";  // thin space
      grouped += digits[k];
    }
    return (n < 0 ? "−" : "") + grouped;
  }
  if (f.size() >= 3 && f[0] == '.' && std::isdigit(static_cast<unsigned char>(f[1])) != 0 && f.size() == 3) {
    const int p = f[1] - '0';
    switch (f[2]) {
      case 'g':
        return fmt::format("{:.{}g}", v, std::max(1, p));
      case 'f':
        return fmt::format("{:.{}f}", v, p);
      case 'e':
        return fmt::format("{:.{}e}", v, p);
      case '%':
        return fmt::format("{:.{}f} %", 100.0 * v, p);
      default:
        break;
    }
  }
  throw std::invalid_argument(
      fmt::format("unknown number format '{}' (.Ng, .Nf, .Ne, .N% with one digit N, or d)", format));
}

std::vector<ProseRef> prose_placeholders(std::string_view text, std::string_view where) {
  std::vector<ProseRef> refs;
  scan(text, where, nullptr, [&](std::string_view body, std::string_view whole) {
    ProseRef r;
    std::string format;
    parse_placeholder(body, r, format, where, whole);
    refs.push_back(std::move(r));
  });
  return refs;
}

std::string expand_prose(std::string_view text, const ProseLookup& lookup, std::string_view where) {
  std::string out;
  scan(text, where, &out, [&](std::string_view body, std::string_view whole) {
    ProseRef r;
    std::string format;
    parse_placeholder(body, r, format, where, whole);
    const std::optional<double> v = lookup.value(r);
    if (!v && !lookup.missing_text.empty()) {
      out += lookup.missing_text;
      return;
    }
    if (!v && lookup.unavailable) {
      if (std::string instead = lookup.unavailable(r); !instead.empty()) {
        out += instead;
        return;
      }
    }
    if (!v) {
      std::string hint;
      if (lookup.keys) {
        const std::string near = nearest(r.key, lookup.keys(r.experiment, r.kind));
        if (!near.empty()) hint = fmt::format(" (nearest: '{}')", near);
      }
      throw std::invalid_argument(fmt::format("{}: placeholder '{}': no {} '{}'{}{}{}", where, whole, r.kind,
                                              r.key, r.experiment.empty() ? "" : " in ", r.experiment, hint));
    }
    try {
      out += format_prose_number(*v, format);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{}: placeholder '{}': {}", where, whole, e.what()));
    }
  });
  return out;
}

std::vector<LiteralNumber> literal_numbers(std::string_view text) {
  // Blank out placeholders and `code` spans, keeping offsets.
  std::string t(text);
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '{' && i + 1 < t.size() && t[i + 1] == '{') {
      ++i;
      continue;
    }
    if (t[i] == '{' || t[i] == '`') {
      const char close = t[i] == '{' ? '}' : '`';
      const auto end = t.find(close, i + 1);
      const std::size_t stop = end == std::string::npos ? t.size() : end + 1;
      for (std::size_t k = i; k < stop; ++k) t[k] = ' ';
      i = stop - 1;
    }
  }
  auto lower_word_before = [&](std::size_t pos) {
    std::size_t e = pos;
    while (e > 0 && (t[e - 1] == ' ' || t[e - 1] == '\n')) --e;
    std::size_t b = e;
    while (b > 0 && (std::isalpha(static_cast<unsigned char>(t[b - 1])) != 0 || t[b - 1] == '.' ||
                     static_cast<unsigned char>(t[b - 1]) >= 0x80))
      --b;
    std::string w = t.substr(b, e - b);
    for (auto& ch : w) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return w;
  };
  static const std::vector<std::string> structural = {"table",     "tables", "fig.",    "figs.",   "figure",
                                                      "figures",   "eq.",    "eqs.",    "§",       "§§",
                                                      "chapter",   "ch.",    "theorem", "section", "lemma",
                                                      "algorithm", "order"};  // a relaxation or expansion
                                                                              // order names a method, as a
                                                                              // figure number names a figure
  std::vector<LiteralNumber> out;
  std::size_t i = 0;
  // End of the last structural number: "Tables 5.1 and 5.2", "Figs. 5.10–5.14", "eqs. 5.39, 5.40" chain on.
  std::size_t structural_end = std::string::npos;
  auto chains = [&](std::size_t from, std::size_t to) {
    if (from == std::string::npos || from > to) return false;
    std::string gap = t.substr(from, to - from);
    for (const char* sep : {"and", "or", "to", "–", "-", ",", " ", "\n"}) {
      for (auto p = gap.find(sep); p != std::string::npos; p = gap.find(sep)) gap.erase(p, std::strlen(sep));
    }
    std::erase(gap, '\n');
    return gap.empty();
  };
  while (i < t.size()) {
    const unsigned char c = static_cast<unsigned char>(t[i]);
    if (std::isdigit(c) == 0) {
      ++i;
      continue;
    }
    // Digits glued to a letter or underscore on the left belong to an identifier (x1, m0020, s0_12).
    if (i > 0 && (std::isalnum(static_cast<unsigned char>(t[i - 1])) != 0 || t[i - 1] == '_')) {
      while (i < t.size() &&
             (std::isalnum(static_cast<unsigned char>(t[i])) != 0 || t[i] == '_' || t[i] == '.'))
        ++i;
      continue;
    }
    std::size_t j = i;
    std::string digits;
    while (j < t.size()) {
      const unsigned char d = static_cast<unsigned char>(t[j]);
      if (std::isdigit(d) != 0) {
        digits += t[j++];
      } else if ((t[j] == '.' || t[j] == ',') && j + 1 < t.size() &&
                 std::isdigit(static_cast<unsigned char>(t[j + 1])) != 0) {
        digits += t[j] == '.' ? '.' : '\0';
        ++j;
      } else if (t.compare(j, 3, "\u2009") == 0 && j + 3 < t.size() &&
                 std::isdigit(static_cast<unsigned char>(t[j + 3])) != 0) {
        j += 3;  // thin-space thousands separator
      } else if (t[j] == ' ' && j + 3 < t.size() && std::isdigit(static_cast<unsigned char>(t[j + 1])) != 0 &&
                 std::isdigit(static_cast<unsigned char>(t[j + 2])) != 0 &&
                 std::isdigit(static_cast<unsigned char>(t[j + 3])) != 0 &&
                 (j + 4 >= t.size() || std::isdigit(static_cast<unsigned char>(t[j + 4])) == 0) &&
                 digits.find('.') == std::string::npos && digits.size() <= 3) {
        ++j;  // "100 000"
      } else {
        break;
      }
    }
    std::erase(digits, '\0');
    // Exponent: 2.75e-4, 1e-9.
    if (j < t.size() && (t[j] == 'e' || t[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < t.size() && (t[k] == '-' || t[k] == '+')) ++k;
      if (k < t.size() && std::isdigit(static_cast<unsigned char>(t[k])) != 0) {
        digits += 'e';
        digits += std::string_view(t).substr(j + 1, k - j - 1);
        while (k < t.size() && std::isdigit(static_cast<unsigned char>(t[k])) != 0) digits += t[k++];
        j = k;
      }
    }
    const std::string before = lower_word_before(i);
    const bool after_structural =
        std::find(structural.begin(), structural.end(), before) != structural.end() ||
        (i > 0 && t.compare(i >= 2 ? i - 2 : 0, 2, "§") == 0);
    const bool tag =
        i > 0 && t[i - 1] == '(' && j < t.size() && t[j] == ')' && (i < 3 || t.compare(i - 3, 2, "SE") != 0);
    const bool group =
        i >= 3 && t[i - 1] == '(' && (t.compare(i - 3, 2, "SE") == 0 || t.compare(i - 3, 2, "SO") == 0);
    const bool dimension = j < t.size() && t[j] == 'D' &&
                           (j + 1 >= t.size() || std::isalpha(static_cast<unsigned char>(t[j + 1])) == 0);
    const bool glued_right = j < t.size() &&
                             (std::isalpha(static_cast<unsigned char>(t[j])) != 0 || t[j] == '_') &&
                             !dimension && t[j] != 'e' && t.compare(j, 1, "×") != 0;
    // "PCM-Exact-11 %", "order-1": a hyphen after a letter joins a label, it is not a minus sign.
    const bool label = i >= 2 && t[i - 1] == '-' && std::isalpha(static_cast<unsigned char>(t[i - 2])) != 0;
    // "6×6" (a matrix size) and "π/2" (a constant fraction).
    const bool times =
        (t.compare(j, 2, "×") == 0 && j + 2 < t.size() &&
         std::isdigit(static_cast<unsigned char>(t[j + 2])) != 0) ||
        (i >= 3 && t.compare(i - 2, 2, "×") == 0 && std::isdigit(static_cast<unsigned char>(t[i - 3])) != 0);
    const bool fraction = i >= 3 && t[i - 1] == '/' && t.compare(i - 3, 2, "π") == 0;
    const bool chained = chains(structural_end, i);
    if (after_structural || chained) structural_end = j;
    if (!(after_structural || tag || group || dimension || glued_right || chained || label || times ||
          fraction)) {
      LiteralNumber n;
      n.text = std::string(text.substr(i, j - i));
      n.value = std::strtod(digits.c_str(), nullptr);
      if (i > 0 && (t[i - 1] == '-' || (i >= 3 && t.compare(i - 3, 3, "−") == 0))) n.value = -n.value;
      n.offset = i;
      out.push_back(std::move(n));
    }
    i = j;
  }
  return out;
}

bool literal_matches(const LiteralNumber& literal, double value) {
  // Half a unit of the literal's last written digit (2.75e-4: of 0.01e-4).
  const std::string& t = literal.text;
  const auto epos = t.find_first_of("eE");
  const std::string mantissa = t.substr(0, epos);
  const auto dot = mantissa.find('.');
  const int decimals = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
  const int exponent = epos == std::string::npos ? 0 : std::atoi(t.c_str() + epos + 1);
  const double half = 0.5 * std::pow(10.0, exponent - decimals) * (1 + 1e-9);
  const double v = literal.value;
  return std::abs(v - value) <= half || std::abs(v - 100.0 * value) <= half;
}

}  // namespace keel::repro
