#pragma once
// Shared pieces of the mesh writers: a buffered text file and round-trip number formatting.
#include <charconv>
#include <fstream>
#include <stdexcept>
#include <string>

namespace tt {
namespace meshio {

// Shortest decimal form that reads back to the same double.
inline std::string number(double value) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, result.ptr);
}

// Collects text and writes it to the file on close(); throws "PATH: cannot ..." on failure.
class TextWriter {
 public:
  explicit TextWriter(std::string path) : path_(std::move(path)) {}
  template <typename T>
  TextWriter& operator<<(const T& value) {
    if constexpr (std::is_arithmetic_v<T>) text_ += std::to_string(value);
    else text_ += value;
    return *this;
  }
  TextWriter& operator<<(double value) {
    text_ += number(value);
    return *this;
  }
  TextWriter& operator<<(char c) {
    text_ += c;
    return *this;
  }
  void close() {
    std::ofstream out(path_, std::ios::binary);
    if (!out) throw std::runtime_error(path_ + ": cannot open for writing");
    out.write(text_.data(), static_cast<std::streamsize>(text_.size()));
    if (!out) throw std::runtime_error(path_ + ": cannot write");
  }

 private:
  std::string path_;
  std::string text_;
};

}  // namespace meshio
}  // namespace tt
