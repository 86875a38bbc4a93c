// Wavefront OBJ: `v x y z [w | r g b]` and `f a b c ...` with corners "i", "i/t", "i//n", "i/t/n".
// Indices are 1-based; negative ones count back from the last vertex defined so far (-1 = the latest). Every other
// statement (vt, vn, o, g, s, usemtl, l, ...) is ignored and listed in a note.
#include <map>
#include <string>
#include <vector>

#include "core/io/cursor.hpp"
#include "core/io/mesh_builder.hpp"
#include "core/io/readers.hpp"

namespace wish::io_detail {

ReadResult read_obj(std::string_view bytes, const ReadLimits& limits) {
  LineCursor lines(bytes, MeshFormat::Obj, limits.max_line_length);
  MeshBuilder builder(limits, MeshFormat::Obj);
  std::map<std::string, std::int64_t> ignored;  // statement -> count, for the note
  std::vector<std::int64_t> corners;
  std::string_view line;
  while (lines.next_content_line(line, '#')) {
    Tokens tokens(line);
    std::string_view keyword;
    tokens.next(keyword);
    if (keyword == "v") {
      double xyz[3];
      for (double& c : xyz) {
        std::string_view token;
        if (!tokens.next(token)) lines.fail("vertex " + std::to_string(builder.vertex_count() + 1) + " has fewer than 3 coordinates");
        if (!parse_double(token, c)) lines.fail("malformed coordinate \"" + std::string(token.substr(0, 40)) + "\"");
      }
      builder.add_vertex(xyz[0], xyz[1], xyz[2], lines.where());
    } else if (keyword == "f") {
      corners.clear();
      std::string_view token;
      while (tokens.next(token)) {
        builder.check_polygon_size(static_cast<std::int64_t>(corners.size()) + 1, lines.where());
        const std::string_view index_text = token.substr(0, token.find('/'));
        std::int64_t index = 0;
        if (!parse_int64(index_text, index)) lines.fail("malformed face corner \"" + std::string(token.substr(0, 40)) + "\"");
        if (index == 0) lines.fail("face corner index 0: OBJ indices start at 1 (or count back from -1)");
        // To 0-based; a relative index that points before the first vertex stays negative and is refused below.
        corners.push_back(index > 0 ? index - 1 : builder.vertex_count() + index);
      }
      builder.add_polygon(corners, lines.where());
    } else {
      // Bounded: at most 32 distinct names are remembered, the rest are counted together.
      std::string name(keyword.substr(0, 16));
      if (ignored.size() >= 32 && !ignored.count(name)) name = "other";
      ++ignored[name];
    }
  }
  ReadResult result;
  result.encoding = MeshEncoding::Ascii;
  result.mesh = builder.finish(result.notes);
  if (!ignored.empty()) {
    std::string note = "ignored OBJ statements:";
    for (const auto& [name, count] : ignored) note += " " + name + " (" + with_commas(count) + ")";
    result.notes.push_back(note);
  }
  return result;
}

}  // namespace wish::io_detail
