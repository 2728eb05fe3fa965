#pragma once
// Errors raised by the core for bad input. Every reader and the scene loader throw
// InputError, whose what() is the single line the user sees: "FILE:LINE: what was expected"
// (or "FILE: key.path: what was expected" for scene keys).
#include <stdexcept>
#include <string>

namespace tt {

class InputError : public std::runtime_error {
 public:
  // line <= 0 means "no line number" (for example, a missing file).
  InputError(const std::string& file, long line, const std::string& message)
      : std::runtime_error(format(file, line, message)), file_(file), line_(line) {}

  const std::string& file() const { return file_; }
  long line() const { return line_; }

  static std::string format(const std::string& file, long line, const std::string& message) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
  }

 private:
  std::string file_;
  long line_;
};

}  // namespace tt
