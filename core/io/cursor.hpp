#pragma once
// Internal to core/io: bounds-checked cursors over an input buffer, with the position of every problem.
//
// Conventions: lines are 1-based and end at "\n" (a preceding "\r" is dropped); byte offsets are 0-based from the
// start of the buffer. No cursor ever reads outside its buffer: every read is checked first, and every failure
// throws an InvalidInputError("parse_error") naming the format and the line or byte offset, in the message and in
// the details ("line" / "byte_offset", "format").

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "core/io/mesh_io.hpp"

namespace wish::io_detail {

// Where a problem was found: a text line (line > 0) or a byte offset (byte_offset >= 0).
struct Location {
  std::int64_t line = 0;
  std::int64_t byte_offset = -1;
};

[[noreturn]] void throw_parse_error(MeshFormat format, Location where, const std::string& what);
[[noreturn]] void throw_limit(const char* limit, std::int64_t value, std::int64_t allowed, const std::string& what);

// "OBJ", "PLY", ...: the format as it starts a message.
std::string format_name(MeshFormat format);

// "1,234,567": counts in messages are read by people.
std::string with_commas(std::int64_t value);

// Strict number parsing of a whole token ("+1.5" and "1e-3" accepted; "1.5x" refused). NaN/Inf parse as such so
// the caller can report them as non-finite rather than as malformed.
bool parse_double(std::string_view token, double& value);
bool parse_int64(std::string_view token, std::int64_t& value);

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits one line into whitespace-separated tokens.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : rest_(line) {}
  bool next(std::string_view& token);
  std::string_view rest() const { return rest_; }  // what `next` has not consumed yet

 private:
  std::string_view rest_;
};

// Line-by-line reading of text, enforcing the line length limit before a line is used.
class LineCursor {
 public:
  LineCursor(std::string_view text, MeshFormat format, std::int64_t max_line_length, std::size_t start = 0);
  // The next line without its terminator; false at the end of the text.
  bool next_line(std::string_view& line);
  // Like next_line, but skips lines that are blank or whose first non-blank character is `comment`.
  bool next_content_line(std::string_view& line, char comment);
  std::int64_t line_number() const { return line_; }  // of the line last returned
  std::size_t offset() const { return pos_; }         // byte offset of the next line
  std::size_t remaining() const { return text_.size() - pos_; }
  Location where() const { return {line_, -1}; }
  [[noreturn]] void fail(const std::string& what) const { throw_parse_error(format_, where(), what); }

 private:
  std::string_view text_;
  MeshFormat format_;
  std::int64_t max_line_length_;
  std::size_t pos_ = 0;
  std::int64_t line_ = 0;
};

// Whitespace-separated tokens across lines (ASCII PLY bodies, where line breaks carry no meaning).
class TokenCursor {
 public:
  TokenCursor(LineCursor& lines) : lines_(lines), tokens_(std::string_view{}) {}
  bool next(std::string_view& token);
  std::string_view expect(const char* what);  // fails with "expected <what>" at the end of the text
  double number(const char* what);
  std::int64_t integer(const char* what);
  const LineCursor& lines() const { return lines_; }

 private:
  LineCursor& lines_;
  Tokens tokens_;
};

// Reads fixed-size binary values in either byte order.
class ByteCursor {
 public:
  ByteCursor(std::string_view bytes, MeshFormat format, std::size_t start = 0) : bytes_(bytes), pos_(start), format_(format) {}
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  bool can_read(std::size_t n) const { return n <= remaining(); }
  // Fails with `what` (e.g. "file ends inside vertex 12 of 100") unless n more bytes exist.
  void require(std::size_t n, const std::string& what) const {
    if (!can_read(n)) fail(what + " (truncated: " + std::to_string(n) + " bytes needed, " + std::to_string(remaining()) + " left)");
  }
  void skip(std::size_t n) { pos_ += n; }  // caller has checked can_read(n)
  template <class T>
  T read(bool big_endian) {  // caller has checked can_read(sizeof(T))
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
    if (big_endian != (std::endian::native == std::endian::big))
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    pos_ += sizeof(T);
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  Location where() const { return {0, static_cast<std::int64_t>(pos_)}; }
  [[noreturn]] void fail(const std::string& what) const { throw_parse_error(format_, where(), what); }

 private:
  std::string_view bytes_;
  std::size_t pos_;
  MeshFormat format_;
};

}  // namespace wish::io_detail
