// Stanford PLY, ascii / binary_little_endian / binary_big_endian.
//
// The header declares elements in file order, each with scalar properties ("property float x") and list properties
// ("property list uchar int vertex_indices"). Vertex x/y/z may have any numeric type; the face list may be called
// vertex_indices or vertex_index, with any count and index types. Every other element and property is skipped
// (binary: by its size, which for lists means reading each count). The body of an ASCII PLY is a token stream.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "core/common/errors.hpp"
#include "core/io/cursor.hpp"
#include "core/io/mesh_builder.hpp"
#include "core/io/readers.hpp"

namespace wish::io_detail {

namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_type(std::string_view name, Type& type) {
  static constexpr std::pair<std::string_view, Type> names[] = {
      {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::UInt8},   {"uint8", Type::UInt8},
      {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::UInt16}, {"uint16", Type::UInt16},
      {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::UInt32},   {"uint32", Type::UInt32},
      {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};
  for (const auto& [n, t] : names)
    if (n == name) { type = t; return true; }
  return false;
}

std::size_t size_of(Type type) {
  switch (type) {
    case Type::Int8: case Type::UInt8: return 1;
    case Type::Int16: case Type::UInt16: return 2;
    case Type::Int32: case Type::UInt32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 1;
}

bool is_integer(Type type) { return type != Type::Float32 && type != Type::Float64; }

struct Property {
  std::string name;
  Type type = Type::Float32;        // of the value, or of the list items
  bool is_list = false;
  Type count_type = Type::UInt8;    // lists only
};

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> properties;
  std::int64_t header_line = 0;
};

// Reads one value of any type from the body, as a double (exact for every PLY integer type).
class ValueReader {
 public:
  ValueReader(std::string_view bytes, std::size_t body_start, MeshEncoding encoding, LineCursor& lines)
      : encoding_(encoding), bytes_(bytes, MeshFormat::Ply, body_start), tokens_(lines) {}

  double value(Type type, const char* what) {
    // ASCII: any number is accepted for any type ("3.0" as a list count); integer() checks integrality.
    if (encoding_ == MeshEncoding::Ascii) return tokens_.number(what);
    bytes_.require(size_of(type), std::string("file ends inside ") + what);
    const bool big = encoding_ == MeshEncoding::BinaryBigEndian;
    switch (type) {
      case Type::Int8: return bytes_.read<std::int8_t>(big);
      case Type::UInt8: return bytes_.read<std::uint8_t>(big);
      case Type::Int16: return bytes_.read<std::int16_t>(big);
      case Type::UInt16: return bytes_.read<std::uint16_t>(big);
      case Type::Int32: return bytes_.read<std::int32_t>(big);
      case Type::UInt32: return bytes_.read<std::uint32_t>(big);
      case Type::Float32: return bytes_.read<float>(big);
      case Type::Float64: return bytes_.read<double>(big);
    }
    return 0;
  }

  // A list count or index: must be an integer value (a float type is accepted when it holds an integer).
  std::int64_t integer(Type type, const char* what) {
    const Location at = where();
    const double v = value(type, what);
    if (!(v == static_cast<double>(static_cast<std::int64_t>(std::clamp(v, -9e18, 9e18)))))
      throw_parse_error(MeshFormat::Ply, at, std::string(what) + " is not an integer");
    return static_cast<std::int64_t>(v);
  }

  void skip(const Property& p, const char* what) {
    if (!p.is_list) { value(p.type, what); return; }
    const std::int64_t n = integer(p.count_type, what);
    if (n < 0) fail(std::string("negative list length in ") + what);
    if (encoding_ == MeshEncoding::Ascii) {
      for (std::int64_t i = 0; i < n; ++i) value(p.type, what);
    } else {
      const auto total = static_cast<unsigned long long>(n) * size_of(p.type);
      bytes_.require(static_cast<std::size_t>(std::min<unsigned long long>(total, std::numeric_limits<std::size_t>::max())),
                     std::string("file ends inside ") + what);
      bytes_.skip(static_cast<std::size_t>(total));
    }
  }

  // Skips `count` rows of a fixed-size element at once, after checking they are there.
  bool skip_fixed_rows(const Element& e) {
    if (encoding_ == MeshEncoding::Ascii) return false;
    std::size_t row = 0;
    for (const auto& p : e.properties) {
      if (p.is_list) return false;
      row += size_of(p.type);
    }
    // Compared by division: count * row could overflow for a hostile count.
    if (row > 0 && static_cast<unsigned long long>(e.count) > bytes_.remaining() / row)
      fail("file ends inside element \"" + e.name + "\" (" + std::to_string(e.count) + " rows of " + std::to_string(row) +
           " bytes, " + std::to_string(bytes_.remaining()) + " bytes left; truncated)");
    bytes_.skip(static_cast<std::size_t>(e.count) * row);
    return true;
  }

  std::size_t remaining() const { return encoding_ == MeshEncoding::Ascii ? tokens_.lines().remaining() : bytes_.remaining(); }
  Location where() const { return encoding_ == MeshEncoding::Ascii ? tokens_.lines().where() : bytes_.where(); }
  [[noreturn]] void fail(const std::string& what) const { throw_parse_error(MeshFormat::Ply, where(), what); }

 private:
  MeshEncoding encoding_;
  ByteCursor bytes_;
  TokenCursor tokens_;
};

}  // namespace

ReadResult read_ply(std::string_view bytes, const ReadLimits& limits) {
  LineCursor lines(bytes, MeshFormat::Ply, limits.max_line_length);
  std::string_view line;
  if (!lines.next_line(line) || line != "ply") lines.fail("missing \"ply\" magic line");

  MeshEncoding encoding = MeshEncoding::Ascii;
  bool have_format = false, have_end = false;
  std::vector<Element> elements;
  std::int64_t unknown_header_lines = 0, first_unknown_line = 0;
  while (!have_end && lines.next_line(line)) {
    Tokens tokens(line);
    std::string_view keyword, token;
    if (!tokens.next(keyword) || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      tokens.next(token);
      if (token == "ascii") encoding = MeshEncoding::Ascii;
      else if (token == "binary_little_endian") encoding = MeshEncoding::BinaryLittleEndian;
      else if (token == "binary_big_endian") encoding = MeshEncoding::BinaryBigEndian;
      else lines.fail("unknown PLY format \"" + std::string(token.substr(0, 40)) + "\"");
      have_format = true;
    } else if (keyword == "element") {
      Element e;
      std::string_view name;
      if (!tokens.next(name) || !tokens.next(token) || !parse_int64(token, e.count) || e.count < 0)
        lines.fail("malformed element declaration (expected: element <name> <count>)");
      if (elements.size() >= 64) lines.fail("more than 64 elements declared");
      e.name = std::string(name.substr(0, 64));
      e.header_line = lines.line_number();
      elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements.empty()) lines.fail("property declared before any element");
      if (elements.back().properties.size() >= 256) lines.fail("more than 256 properties in one element");
      Property p;
      tokens.next(token);
      if (token == "list") {
        p.is_list = true;
        std::string_view count_type, item_type;
        if (!tokens.next(count_type) || !parse_type(count_type, p.count_type) || !is_integer(p.count_type) ||
            !tokens.next(item_type) || !parse_type(item_type, p.type))
          lines.fail("malformed list property (expected: property list <integer type> <type> <name>)");
      } else if (!parse_type(token, p.type)) {
        lines.fail("unknown property type \"" + std::string(token.substr(0, 40)) + "\"");
      }
      if (!tokens.next(token)) lines.fail("property without a name");
      p.name = std::string(token.substr(0, 64));
      elements.back().properties.push_back(std::move(p));
    } else if (keyword == "end_header") {
      have_end = true;
    } else {
      // Some exporters write free text into the header (Blender 2.47: "Created by ..."); it declares nothing, so it
      // is skipped, and said so.
      if (unknown_header_lines++ == 0) first_unknown_line = lines.line_number();
    }
  }
  if (!have_end) lines.fail("the header has no end_header line");
  if (!have_format) lines.fail("the header has no format line");

  ValueReader reader(bytes, lines.offset(), encoding, lines);
  MeshBuilder builder(limits, MeshFormat::Ply);
  std::vector<std::string> skipped;
  std::vector<std::int64_t> corners;
  bool have_vertices = false;
  for (const Element& e : elements) {
    if (e.name == "vertex" && !have_vertices) {
      have_vertices = true;
      int axis_of[3] = {-1, -1, -1};
      for (std::size_t i = 0; i < e.properties.size(); ++i)
        for (int k = 0; k < 3; ++k)
          if (!e.properties[i].is_list && e.properties[i].name == std::string(1, static_cast<char>('x' + k))) axis_of[k] = static_cast<int>(i);
      if (axis_of[0] < 0 || axis_of[1] < 0 || axis_of[2] < 0)
        throw_parse_error(MeshFormat::Ply, {e.header_line, -1}, "the vertex element lacks one of the scalar properties x, y, z");
      std::size_t min_row = 0;
      for (const auto& p : e.properties) min_row += encoding == MeshEncoding::Ascii ? 2 : (p.is_list ? size_of(p.count_type) : size_of(p.type));
      builder.expect_vertices(e.count, static_cast<std::int64_t>(reader.remaining() / std::max<std::size_t>(min_row, 1)));
      for (std::int64_t v = 0; v < e.count; ++v) {
        const Location at = reader.where();
        double xyz[3] = {0, 0, 0};
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
          const int axis = static_cast<int>(std::find(axis_of, axis_of + 3, static_cast<int>(i)) - axis_of);
          if (axis < 3) xyz[axis] = reader.value(e.properties[i].type, "a vertex coordinate");
          else reader.skip(e.properties[i], "a vertex property");
        }
        builder.add_vertex(xyz[0], xyz[1], xyz[2], at);
      }
    } else if (e.name == "face") {
      const auto list = std::find_if(e.properties.begin(), e.properties.end(), [](const Property& p) {
        return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
      });
      if (list == e.properties.end())
        throw_parse_error(MeshFormat::Ply, {e.header_line, -1}, "the face element has no list property vertex_indices or vertex_index");
      std::size_t min_row = 0;
      for (const auto& p : e.properties) min_row += encoding == MeshEncoding::Ascii ? 2 : (p.is_list ? size_of(p.count_type) : size_of(p.type));
      builder.expect_polygons(e.count, static_cast<std::int64_t>(reader.remaining() / std::max<std::size_t>(min_row, 1)));
      for (std::int64_t f = 0; f < e.count; ++f) {
        const Location at = reader.where();
        for (const Property& p : e.properties) {
          if (&p != &*list) { reader.skip(p, "a face property"); continue; }
          const std::int64_t n = reader.integer(p.count_type, "a face corner count");
          builder.check_polygon_size(n, at);
          corners.clear();
          for (std::int64_t k = 0; k < n; ++k) corners.push_back(reader.integer(p.type, "a face vertex index"));
        }
        builder.add_polygon(corners, at);
      }
    } else {
      skipped.push_back(e.name + " (" + with_commas(e.count) + ")");
      // Rows without properties take no bytes; skipping them must not loop 10^12 times.
      if (e.properties.empty() || reader.skip_fixed_rows(e)) continue;
      const std::string what = "element \"" + e.name + "\"";
      for (std::int64_t r = 0; r < e.count; ++r)
        for (const Property& p : e.properties) reader.skip(p, what.c_str());
    }
  }

  ReadResult result;
  result.encoding = encoding;
  result.mesh = builder.finish(result.notes);
  if (unknown_header_lines > 0)
    result.notes.push_back("ignored " + with_commas(unknown_header_lines) + " unrecognised PLY header lines (first: line " +
                           std::to_string(first_unknown_line) + ")");
  if (!skipped.empty()) {
    std::string note = "ignored PLY elements:";
    for (const auto& s : skipped) note += " " + s;
    result.notes.push_back(note);
  }
  return result;
}

}  // namespace wish::io_detail
