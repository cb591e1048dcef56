// The tokeniser of Siconos' text dumps (siconos.cpp, siconos_fc3d.cpp): the file is a stream of
// whitespace-separated tokens (Siconos reads it with fscanf); each token remembers its line so
// that every error names the file and the line.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <istream>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"

namespace cbps {

struct Token {
  std::string text;
  int line = 0;
};

/// Reads the fields of one file in order; every error names the file and the line.
class TokenReader {
 public:
  TokenReader(std::istream& in, const std::string& source) : path_(source) {
    std::ostringstream text;
    text << in.rdbuf();
    split(text.str());
  }

  [[noreturn]] void fail(int line, const std::string& why) const {
    throw InputError(path_ + ": line " + std::to_string(line) + ": " + why);
  }

  /// The next token, or a failure naming `what` at the end of the file.
  const Token& next(const std::string& what) {
    if (pos_ >= tokens_.size()) fail(last_line_, "end of file where " + what + " was expected");
    return tokens_[pos_++];
  }

  /// The line of the token read last.
  int line() const { return pos_ == 0 ? 1 : tokens_[pos_ - 1].line; }

  /// How many tokens are left to read.
  std::size_t remaining() const { return tokens_.size() - pos_; }
  /// Where the reader stands (a token index), and back there.
  std::size_t position() const { return pos_; }
  void rewind(std::size_t position) { pos_ = position; }
  /// The token `ahead` places from the next one, null past the end.
  const Token* peek(std::size_t ahead = 0) const {
    return pos_ + ahead < tokens_.size() ? &tokens_[pos_ + ahead] : nullptr;
  }

  /// How many of the tokens left, from the next one on, are numbers before the first that is not.
  std::size_t leading_numbers() const {
    std::size_t count = 0;
    double value = 0;
    while (pos_ + count < tokens_.size() && parse_number(tokens_[pos_ + count].text, value))
      ++count;
    return count;
  }

  /// A whole token as an integer.
  long next_integer(const std::string& what) {
    const Token& t = next(what);
    errno = 0;
    char* end = nullptr;
    const long value = std::strtol(t.text.c_str(), &end, 10);
    if (end == t.text.c_str() || *end != '\0' || errno == ERANGE)
      fail(t.line, "expected an integer " + what + ", found '" + t.text + "'");
    return value;
  }

  /// A whole token as a finite double; describe() names it (called only on failure).
  template <class Describe>
  double next_number(const Describe& describe) {
    if (pos_ >= tokens_.size()) next(describe());
    const Token& t = tokens_[pos_++];
    double value = 0;
    if (!parse_token(t.text, value))
      fail(t.line, "expected a number " + describe() + ", found '" + t.text + "'");
    if (!std::isfinite(value)) fail(t.line, describe() + " is not finite ('" + t.text + "')");
    return value;
  }

 private:
  void split(const std::string& text) {
    int line = 1;
    std::string current;
    for (char c : text) {
      const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
      if (space) {
        if (!current.empty()) tokens_.push_back({current, line});
        current.clear();
        if (c == '\n') ++line;
      } else {
        current.push_back(c);
      }
    }
    if (!current.empty()) tokens_.push_back({current, line});
    last_line_ = tokens_.empty() ? 1 : tokens_.back().line;
  }

  std::string path_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  int last_line_ = 1;
};

}  // namespace cbps
