#include "graph/text_records.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <system_error>

#include "core/parse.hpp"
#include "graph/parse_error.hpp"

namespace keel::graph {

ParseError::ParseError(std::string file, int line, const std::string& message)
    : std::runtime_error(line > 0 ? fmt::format("{}:{}: {}", file, line, message)
                                  : fmt::format("{}: {}", file, message)),
      file_(std::move(file)),
      line_(line) {}

std::string read_file_text(const std::filesystem::path& file) {
  // One pass through core::read_whole_file: pipes and FIFOs work, a directory is named as one.
  std::string text;
  if (auto why = core::read_whole_file(file, text); !why.empty()) throw ParseError(file.string(), 0, why);
  return text;
}

std::string read_stream_text(std::istream& in, const std::string& name) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw ParseError(name, 0, "read error");
  return text;
}

void write_file_atomically(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", tmp.string()));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.flush();
    if (!out) {
      out.close();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error(fmt::format("{}: write failed", tmp.string()));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(fmt::format("{}: cannot rename the temporary file into place", file.string()));
  }
}

std::string fmt17(double v) { return fmt::format("{:.17g}", v); }

void fail_at(const std::string& name, int line, const std::string& msg) { throw ParseError(name, line, msg); }

RecordScanner::RecordScanner(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {}
RecordScanner::RecordScanner(std::string_view text, std::string name, std::string kind)
    : text_(text), name_(std::move(name)), kind_(std::move(kind)) {}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
}  // namespace

bool RecordScanner::next() {
  names_ = {};
  while (pos_ < text_.size()) {
    const std::size_t nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
    std::string_view ln = text_.substr(pos_, end - pos_);
    pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
    ++line_;
    if (const auto hash = ln.find('#'); hash != std::string_view::npos) ln = ln.substr(0, hash);
    fields_.clear();
    std::size_t i = 0;
    while (i < ln.size()) {
      while (i < ln.size() && is_space(ln[i])) ++i;
      const std::size_t b = i;
      while (i < ln.size() && !is_space(ln[i])) ++i;
      if (i > b) fields_.push_back(ln.substr(b, i - b));
    }
    if (!fields_.empty()) {
      if (!kind_.empty()) fields_.insert(fields_.begin(), std::string_view(kind_));
      return true;
    }
  }
  return false;
}

void RecordScanner::expect(std::span<const char* const> names) {
  names_ = names;
  const std::size_t n = size();
  const char* after = kind_.empty() ? " fields after the tag, found " : " fields, found ";
  if (n < names.size()) {
    fail(fmt::format("{}: expected {}{}{} (truncated line?): field {} ({}) is missing", tag(), names.size(),
                     after, n, n + 1, names[n]));
  }
  if (n > names.size()) {
    fail(fmt::format("{}: expected {}{}{}: field {} {} is one too many", tag(), names.size(), after, n,
                     names.size() + 1, core::quote_token(fields_[names.size() + 1])));
  }
}

std::string RecordScanner::describe_field(std::size_t k) const {
  if (k >= 1 && k <= names_.size()) return fmt::format("{} field {} ({})", tag(), k, names_[k - 1]);
  return fmt::format("{} field {}", tag(), k);
}

void RecordScanner::fail(const std::string& msg) const { throw ParseError(name_, line_, msg); }

void RecordScanner::fail_field(std::size_t k, const std::string& msg) const {
  fail(fmt::format("{}: {}", describe_field(k), msg));
}

void RecordScanner::fail_fields(std::size_t first, std::size_t last, const std::string& msg) const {
  if (first >= 1 && last <= names_.size())
    fail(fmt::format("{} fields {}-{} ({}..{}): {}", tag(), first, last, names_[first - 1], names_[last - 1],
                     msg));
  fail(fmt::format("{} fields {}-{}: {}", tag(), first, last, msg));
}

double RecordScanner::number(std::size_t k) const {
  double v = 0.0;
  if (auto why = core::parse_real(fields_[k], v); !why.empty()) fail_field(k, why);
  return v;
}

void RecordScanner::numbers(std::size_t first, std::size_t last, double* out) const {
  for (std::size_t k = first; k <= last; ++k) *out++ = number(k);
}

int RecordScanner::id(std::size_t k) const {
  std::int64_t v = 0;
  if (auto why = core::parse_integer(fields_[k], 0, std::numeric_limits<int>::max() - 1, v, "an integer id");
      !why.empty())
    fail_field(k, why);
  return static_cast<int>(v);
}

}  // namespace keel::graph
