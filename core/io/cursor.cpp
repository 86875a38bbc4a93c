#include "core/io/cursor.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>

#include "core/common/errors.hpp"

namespace wish::io_detail {

void throw_parse_error(MeshFormat format, Location where, const std::string& what) {
  ErrorDetails details{{"format", std::string(to_string(format))}};
  std::string position;
  if (where.line > 0) {
    details["line"] = where.line;
    position = "line " + std::to_string(where.line);
  } else if (where.byte_offset >= 0) {
    details["byte_offset"] = where.byte_offset;
    position = "byte " + std::to_string(where.byte_offset);
  }
  throw InvalidInputError("parse_error", format_name(format) + (position.empty() ? "" : ", " + position) + ": " + what, std::move(details));
}

void throw_limit(const char* limit, std::int64_t value, std::int64_t allowed, const std::string& what) {
  throw LimitExceededError(what + ": " + with_commas(value) + " exceeds the limit of " + with_commas(allowed) + " (" + limit + ")",
                           {{"limit", std::string(limit)}, {"value", value}, {"allowed", allowed}});
}

std::string format_name(MeshFormat format) {
  std::string name = to_string(format);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return name;
}

std::string with_commas(std::int64_t value) {
  const auto bits = static_cast<unsigned long long>(value);
  std::string digits = std::to_string(value < 0 ? 0ull - bits : bits);  // no overflow for INT64_MIN
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return value < 0 ? "-" + out : out;
}

bool parse_double(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);  // from_chars refuses a leading '+'
  if (token.empty()) return false;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    // "1e999" / "1e-999": well-formed but not representable. strtod gives +-HUGE_VAL (then reported as non-finite)
    // or the underflowed value, which is what the number means.
    value = std::strtod(std::string(token).c_str(), nullptr);
    return true;
  }
  return ec == std::errc();
}

bool parse_int64(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

bool Tokens::next(std::string_view& token) {
  std::size_t i = 0;
  while (i < rest_.size() && is_space(rest_[i])) ++i;
  std::size_t j = i;
  while (j < rest_.size() && !is_space(rest_[j])) ++j;
  token = rest_.substr(i, j - i);
  rest_.remove_prefix(j);
  return !token.empty();
}

LineCursor::LineCursor(std::string_view text, MeshFormat format, std::int64_t max_line_length, std::size_t start)
    : text_(text), format_(format), max_line_length_(max_line_length), pos_(std::min(start, text.size())) {}

bool LineCursor::next_line(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  ++line_;
  // Search at most max_line_length + 1 bytes, so a 2 GB line is refused after reading 1 MB of it.
  const std::size_t window = std::min<std::size_t>(text_.size() - pos_, static_cast<std::size_t>(max_line_length_) + 1);
  const char* start = text_.data() + pos_;
  const void* newline = std::memchr(start, '\n', window);
  std::size_t length = newline ? static_cast<std::size_t>(static_cast<const char*>(newline) - start) : window;
  if (!newline && window < text_.size() - pos_)
    throw_limit("max_line_length", static_cast<std::int64_t>(length), max_line_length_,
                std::string(to_string(format_)) + " line " + std::to_string(line_) + " is too long");
  pos_ += length + (newline ? 1 : 0);
  if (length > 0 && start[length - 1] == '\r') --length;
  if (static_cast<std::int64_t>(length) > max_line_length_)
    throw_limit("max_line_length", static_cast<std::int64_t>(length), max_line_length_,
                std::string(to_string(format_)) + " line " + std::to_string(line_) + " is too long");
  line = std::string_view(start, length);
  return true;
}

bool LineCursor::next_content_line(std::string_view& line, char comment) {
  while (next_line(line)) {
    std::size_t i = 0;
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size() || line[i] == comment) continue;
    line.remove_prefix(i);
    return true;
  }
  return false;
}

bool TokenCursor::next(std::string_view& token) {
  while (!tokens_.next(token)) {
    std::string_view line;
    if (!lines_.next_line(line)) return false;
    tokens_ = Tokens(line);
  }
  return true;
}

std::string_view TokenCursor::expect(const char* what) {
  std::string_view token;
  if (!next(token)) lines_.fail(std::string("expected ") + what + ", found the end of the file");
  return token;
}

double TokenCursor::number(const char* what) {
  const std::string_view token = expect(what);
  double value = 0;
  if (!parse_double(token, value)) lines_.fail(std::string("expected ") + what + ", found \"" + std::string(token.substr(0, 40)) + "\"");
  return value;
}

std::int64_t TokenCursor::integer(const char* what) {
  const std::string_view token = expect(what);
  std::int64_t value = 0;
  if (!parse_int64(token, value)) lines_.fail(std::string("expected ") + what + ", found \"" + std::string(token.substr(0, 40)) + "\"");
  return value;
}

}  // namespace wish::io_detail
