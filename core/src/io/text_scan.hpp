// Internal: line and token scanning over the bytes of a text mesh file, and number parsing that
// does not depend on the locale. Nothing here allocates per token.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace depath::io {

/// Walks `bytes` line by line ("\n", "\r\n" or "\r" endings).
class LineScanner {
 public:
  explicit LineScanner(std::string_view bytes, size_t start = 0) : bytes_(bytes), pos_(start) {}
  /// Next line without its ending; false at the end of the bytes.
  bool next(std::string_view& line);
  /// 1-based number of the line last returned.
  uint64_t line_number() const { return line_; }
  /// "line N", for messages.
  std::string where() const { return "line " + std::to_string(line_); }
  uint64_t bytes_left() const { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  size_t pos_;
  uint64_t line_ = 0;
};

/// Splits one line at blanks (space, tab, vertical tab, form feed).
class Tokens {
 public:
  explicit Tokens(std::string_view line) : rest_(line) {}
  bool next(std::string_view& token);
  std::string_view rest() const { return rest_; }

 private:
  std::string_view rest_;
};

/// The part of a line before a '#' comment.
std::string_view strip_comment(std::string_view line);

/// Parses a whole token as a number: as a float rounded once (`single`), or as a double. "nan" and
/// "inf" parse (the caller reports them as non-finite); a number too large becomes infinity, one
/// too small becomes 0 or a denormal. nullopt if the token is not a number.
std::optional<double> parse_real(std::string_view token, bool single);

/// Parses a whole token as a decimal integer; nullopt if it is not one or does not fit.
std::optional<int64_t> parse_integer(std::string_view token);

/// The token quoted for a message, cut to 40 characters and with unprintable bytes escaped.
std::string quoted(std::string_view token);

}  // namespace depath::io
