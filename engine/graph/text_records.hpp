// keel::graph — the line/field scanner of every reader, also for the faces' own text files (a split's
// labels), and the file helpers of every writer: reading a file whole, writing through a temporary name,
// "%.17g". Used by headers (app, python), not exported by the keel.graph facade.
#pragma once

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace keel::graph {

/// The whole file as a string; ParseError(file, 0, "cannot open ...") when it cannot be read.
std::string read_file_text(const std::filesystem::path& file);
/// The whole stream as a string; ParseError when the stream goes bad.
std::string read_stream_text(std::istream& in, const std::string& name);
/// Writes `text` to `file` through a temporary name in the same folder and a rename.
void write_file_atomically(const std::filesystem::path& file, const std::string& text);

/// "%.17g" of v.
std::string fmt17(double v);

/// Walks the records of a text file: lines with '#' comments removed, blank lines skipped, fields split on
/// spaces, tabs, CR, VT and FF. Field 0 is the tag; "field k" in messages counts from 1 after the tag.
class RecordScanner {
 public:
  RecordScanner(std::string_view text, std::string name);
  /// Untagged records (`id x y theta`, TUM lines): every field is data; tag() returns `kind` for messages and
  /// field 1 is the first field of the line.
  RecordScanner(std::string_view text, std::string name, std::string kind);
  RecordScanner(const RecordScanner&) = delete;
  RecordScanner& operator=(const RecordScanner&) = delete;

  /// Advances to the next record; false at the end of the text.
  bool next();
  int line() const { return line_; }
  std::string_view tag() const { return fields_.front(); }
  const std::string& name() const { return name_; }
  /// Number of fields after the tag.
  std::size_t size() const { return fields_.size() - 1; }
  std::string_view field(std::size_t k) const { return fields_[k]; }

  /// Declares the field names of the current record and checks the count (truncated line / extra fields).
  void expect(std::span<const char* const> names);
  /// Field k (1-based, after the tag) as a finite double / a non-negative int id.
  double number(std::size_t k) const;
  int id(std::size_t k) const;
  /// Fields first..last (1-based, inclusive) as doubles.
  void numbers(std::size_t first, std::size_t last, double* out) const;

  /// "name:line: TAG field k (fname): msg"
  [[noreturn]] void fail_field(std::size_t k, const std::string& msg) const;
  /// "name:line: TAG fields a-b (fa..fb): msg"
  [[noreturn]] void fail_fields(std::size_t first, std::size_t last, const std::string& msg) const;
  /// "name:line: msg"
  [[noreturn]] void fail(const std::string& msg) const;
  /// "TAG field k (fname)", for messages raised later about this record.
  std::string describe_field(std::size_t k) const;

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::string name_;
  std::string kind_;  // non-empty: untagged records
  int line_ = 0;
  std::vector<std::string_view> fields_;
  std::span<const char* const> names_;
};

/// "name:line: msg" as a ParseError (line 0: "name: msg").
[[noreturn]] void fail_at(const std::string& name, int line, const std::string& msg);

}  // namespace keel::graph
