// keel::graph — the one error type of every reader: a message that names the file, the line and the field.
//   what() = "data.g2o:17: EDGE_SE2 field 5 (dtheta): 'abc' is not a number"
// Errors that belong to no single line (missing odometry edge, empty file, cannot open) have line() == 0 and
// read "data.g2o: ..." (they still name the line of the record that exposed the problem inside the message
// where one exists).
#pragma once

#include <stdexcept>
#include <string>

namespace keel::graph {

class ParseError : public std::runtime_error {
 public:
  ParseError(std::string file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 1-based; 0 when the error is about the whole file

 private:
  std::string file_;
  int line_ = 0;
};

}  // namespace keel::graph
