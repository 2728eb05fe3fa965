#include "text_scanner.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace tt {
namespace meshio {

namespace {

bool isBinaryByte(unsigned char c) {
  return c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v';
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

}  // namespace

std::string loadTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open file (missing or unreadable)");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  if (in.bad()) throw InputError(path, 0, "cannot read file");
  bool blank = true;
  long line = 1;
  for (unsigned char c : text) {
    if (c == '\n') {
      ++line;
    } else if (isBinaryByte(c)) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", c);
      throw InputError(path, line, std::string("unexpected binary byte ") + hex +
                                       ", expected an ASCII text file");
    } else if (!isSpace(static_cast<char>(c))) {
      blank = false;
    }
  }
  if (blank) throw InputError(path, 0, "file is empty");
  return text;
}

std::string quoted(std::string_view token) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c < 0x20 || c >= 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (token.size() > kMax) out += "...";
  return out + "'";
}

Scanner::Scanner(const std::string& path, const std::string& text, char commentChar)
    : Scanner(path, text, 0, text.size(), 1, commentChar) {}

Scanner::Scanner(const std::string& path, const std::string& text, std::size_t begin,
                 std::size_t end, long firstLine, char commentChar)
    : path_(path), text_(text), pos_(begin), end_(end), nextLineNo_(firstLine),
      line_(firstLine), comment_(commentChar) {}

void Scanner::split(std::string_view text) {
  tokens_.clear();
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && isSpace(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !isSpace(text[i])) ++i;
    if (i > start) tokens_.push_back(text.substr(start, i - start));
  }
}

bool Scanner::nextLine() {
  while (pos_ < end_) {
    std::size_t stop = text_.find('\n', pos_);
    if (stop == std::string::npos || stop > end_) stop = end_;
    std::string_view text(text_.data() + pos_, stop - pos_);
    pos_ = stop < end_ ? stop + 1 : end_;
    line_ = nextLineNo_++;
    if (comment_) {
      const std::size_t c = text.find(comment_);
      if (c != std::string_view::npos) text = text.substr(0, c);
    }
    split(text);
    if (tokens_.empty()) continue;
    while (!text.empty() && isSpace(text.back())) text.remove_suffix(1);
    while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
    lineText_ = text;
    tokenIndex_ = 0;
    return true;
  }
  tokens_.clear();
  lineText_ = {};
  tokenIndex_ = 0;
  return false;
}

bool Scanner::nextToken(std::string_view& token) {
  while (tokenIndex_ >= tokens_.size())
    if (!nextLine()) return false;
  token = tokens_[tokenIndex_++];
  return true;
}

std::string_view Scanner::requireToken(const std::string& what) {
  std::string_view token;
  if (!nextToken(token)) fail("expected " + what + ", got end of file");
  return token;
}

void Scanner::requireLine(const std::string& what) {
  if (!nextLine()) fail("expected " + what + ", got end of file");
}

void Scanner::requireTokens(std::size_t n, const std::string& what) const {
  if (tokens_.size() != n)
    fail("expected " + what + " (" + std::to_string(n) + " values), got " +
         std::to_string(tokens_.size()) + " values");
}

void Scanner::requireAtLeast(std::size_t n, const std::string& what) const {
  if (tokens_.size() < n)
    fail("expected " + what + " (at least " + std::to_string(n) + " values), got " +
         std::to_string(tokens_.size()) + " values");
}

void Scanner::fail(const std::string& message) const { failAt(line_, message); }

void Scanner::failAt(long line, const std::string& message) const {
  throw InputError(path_, line, message);
}

double Scanner::toDouble(std::string_view token, const std::string& what) const {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ptr != t.data() + t.size() || (ec != std::errc() && ec != std::errc::result_out_of_range))
    fail("expected " + what + ", got " + quoted(token));
  if (ec == std::errc::result_out_of_range || !std::isfinite(value))
    fail("expected " + what + ", got non-finite value " + quoted(token));
  return value;
}

long long Scanner::toInt(std::string_view token, const std::string& what) const {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ptr != t.data() + t.size() || ec == std::errc::invalid_argument)
    fail("expected " + what + " (an integer), got " + quoted(token));
  if (ec == std::errc::result_out_of_range)
    fail("expected " + what + ", got out-of-range integer " + quoted(token));
  return value;
}

long long Scanner::toInt(std::string_view token, long long lo, long long hi,
                         const std::string& what) const {
  const long long value = toInt(token, what);
  if (value < lo || value > hi)
    fail("expected " + what + " in [" + std::to_string(lo) + ", " + std::to_string(hi) +
         "], got " + std::to_string(value));
  return value;
}

void Scanner::checkCount(long long count, const std::string& items) const {
  if (count < 0) fail("expected a non-negative number of " + items + ", got " + std::to_string(count));
  if (static_cast<unsigned long long>(count) > bytesLeft() + 1)
    fail("declared " + std::to_string(count) + " " + items + " but only " +
         std::to_string(bytesLeft()) + " bytes follow");
}

void checkDistinct(const Scanner& s, const long long* ids, int count) {
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < i; ++j)
      if (ids[i] == ids[j])
        s.fail("expected distinct nodes in an element, node " + std::to_string(ids[i]) +
               " is repeated");
}

}  // namespace meshio
}  // namespace tt
