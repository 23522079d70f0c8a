#include "io/text_scan.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace depath::io {

bool LineScanner::next(std::string_view& line) {
  if (pos_ >= bytes_.size()) return false;
  size_t end = pos_;
  while (end < bytes_.size() && bytes_[end] != '\n' && bytes_[end] != '\r') ++end;
  line = bytes_.substr(pos_, end - pos_);
  if (end < bytes_.size() && bytes_[end] == '\r') ++end;
  if (end < bytes_.size() && bytes_[end] == '\n' && (end == pos_ + line.size() || bytes_[end - 1] == '\r'))
    ++end;
  pos_ = end;
  ++line_;
  return true;
}

namespace {
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
}  // namespace

bool Tokens::next(std::string_view& token) {
  size_t i = 0;
  while (i < rest_.size() && is_blank(rest_[i])) ++i;
  if (i == rest_.size()) {
    rest_ = {};
    return false;
  }
  size_t j = i;
  while (j < rest_.size() && !is_blank(rest_[j])) ++j;
  token = rest_.substr(i, j - i);
  rest_ = rest_.substr(j);
  return true;
}

std::string_view strip_comment(std::string_view line) {
  const size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

namespace {
template <typename T>
std::optional<double> parse_as(std::string_view token) {
  const char* first = token.data();
  const char* last = first + token.size();
  const bool negative = first != last && *first == '-';
  if (first != last && *first == '+') ++first;  // from_chars refuses a leading '+'
  T value{};
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ptr != last || first == last) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Out of range: overflow or underflow. A non-zero digit before the exponent with a negative
    // exponent is an underflow; anything else here overflowed.
    const size_t e = token.find_first_of("eE");
    const bool underflow = e != std::string_view::npos && e + 1 < token.size() && token[e + 1] == '-';
    if (underflow) return negative ? -0.0 : 0.0;
    return negative ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  }
  if (ec != std::errc()) return std::nullopt;
  return static_cast<double>(value);
}
}  // namespace

std::optional<double> parse_real(std::string_view token, bool single) {
  return single ? parse_as<float>(token) : parse_as<double>(token);
}

std::optional<int64_t> parse_integer(std::string_view token) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec != std::errc() || ptr != last || first == last) return std::nullopt;
  return value;
}

std::string quoted(std::string_view token) {
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (token.size() > 40) out += "...";
  return out + "'";
}

}  // namespace depath::io
