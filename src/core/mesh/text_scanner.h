#pragma once
// Shared pieces of the ASCII mesh readers: loading a file with the checks every reader needs
// (missing, empty, binary), walking it line by line or token by token with line numbers,
// and strict number parsing that names the file and line in its InputError.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "tissue_trainer/core/error.h"

namespace tt {
namespace meshio {

// Reads the whole file. Throws InputError for a missing or empty file and for binary data
// (NUL or other control bytes), naming the line of the first offending byte.
std::string loadTextFile(const std::string& path);

// A token for messages: non-printable bytes escaped, long tokens shortened.
std::string quoted(std::string_view token);

// Walks a range [begin, end) of a text line by line (blank lines and, when commentChar is
// set, everything after it are skipped) or token by token across lines.
class Scanner {
 public:
  Scanner(const std::string& path, const std::string& text, char commentChar = 0);
  Scanner(const std::string& path, const std::string& text, std::size_t begin, std::size_t end,
          long firstLine, char commentChar = 0);

  const std::string& path() const { return path_; }
  long lineNo() const { return line_; }
  std::size_t bytesLeft() const { return end_ - pos_; }

  // Line mode: moves to the next non-blank line and splits it into tokens.
  bool nextLine();
  std::string_view line() const { return lineText_; }
  std::size_t size() const { return tokens_.size(); }
  std::string_view operator[](std::size_t i) const { return tokens_[i]; }
  const std::string_view* tokens() const { return tokens_.data(); }

  // Token mode: the next whitespace-separated token, across lines. False at the end.
  bool nextToken(std::string_view& token);
  // Marks the tokens of the current line as used, so nextToken starts on the next line.
  void finishLine() { tokenIndex_ = tokens_.size(); }
  // Next token or an error "expected WHAT, got end of file".
  std::string_view requireToken(const std::string& what);

  // Line mode: the next non-blank line or an error "expected WHAT, got end of file".
  void requireLine(const std::string& what);
  // Current line must have exactly n tokens (else "expected WHAT, got K values").
  void requireTokens(std::size_t n, const std::string& what) const;
  void requireAtLeast(std::size_t n, const std::string& what) const;

  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void failAt(long line, const std::string& message) const;

  // Strict conversions: the whole token must be a number; doubles must be finite.
  double toDouble(std::string_view token, const std::string& what) const;
  long long toInt(std::string_view token, const std::string& what) const;
  // An integer in [lo, hi].
  long long toInt(std::string_view token, long long lo, long long hi, const std::string& what) const;

  // Rejects a negative count or one larger than the bytes left (every item needs at least
  // one byte), so that absurd counts fail early with a clear message. Readers still never
  // reserve from a count: they grow as they read.
  void checkCount(long long count, const std::string& items) const;

 private:
  void split(std::string_view text);

  std::string path_;
  const std::string& text_;
  std::size_t pos_;
  std::size_t end_;
  long nextLineNo_;
  long line_ = 0;
  char comment_;
  std::string_view lineText_;
  std::vector<std::string_view> tokens_;
  // Token mode state: the remaining tokens of the current line.
  std::size_t tokenIndex_ = 0;
};

// Fails at the current line when the node ids of one element are not distinct.
void checkDistinct(const Scanner& s, const long long* ids, int count);

}  // namespace meshio
}  // namespace tt
