// Geomview OFF and its variants COFF, NOFF, CNOFF, STOFF (extra per-vertex values are skipped):
//   [ST][C][N]OFF            (the counts may follow on the same line)
//   #vertices #faces #edges
//   x y z [extras]           one vertex per line
//   n i0 ... i(n-1) [color]  one face per line, 0-based indices
// '#' starts a comment anywhere. 4OFF / nOFF (other dimensions) and binary OFF are refused as unsupported.
#include <string>
#include <vector>

#include "core/common/errors.hpp"
#include "core/io/cursor.hpp"
#include "core/io/mesh_builder.hpp"
#include "core/io/readers.hpp"

namespace wish::io_detail {

namespace {

std::string_view strip_comment(std::string_view line) {
  const auto hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

// Next line that has content once comments are stripped.
bool next_data_line(LineCursor& lines, std::string_view& line) {
  while (lines.next_content_line(line, '#')) {
    line = strip_comment(line);
    Tokens probe(line);
    std::string_view token;
    if (probe.next(token)) return true;
  }
  return false;
}

void refuse_unsupported(const std::string& why) {
  throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format", "OFF: " + why, {{"format", std::string("off")}});
}

}  // namespace

ReadResult read_off(std::string_view bytes, const ReadLimits& limits) {
  LineCursor lines(bytes, MeshFormat::Off, limits.max_line_length);
  std::string_view line;
  if (!next_data_line(lines, line)) lines.fail("missing OFF header");
  Tokens header(line);
  std::string_view keyword;
  header.next(keyword);
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") lines.fail("expected an OFF header keyword");
  if (keyword.find('4') != std::string_view::npos || keyword.find('n') != std::string_view::npos)
    refuse_unsupported("\"" + std::string(keyword) + "\" (vertices of other than 3 dimensions) is not supported");

  // Counts: on the header line after the keyword, or on the next data line.
  Tokens counts = header;
  std::string_view token;
  if (!Tokens(counts.rest()).next(token)) {
    if (!next_data_line(lines, line)) lines.fail("missing vertex and face counts");
    counts = Tokens(line);
  } else if (token == "BINARY") {
    refuse_unsupported("binary OFF is not supported");
  }
  std::int64_t nv = 0, nf = 0;
  if (!counts.next(token) || !parse_int64(token, nv)) lines.fail("expected the vertex count");
  if (!counts.next(token) || !parse_int64(token, nf)) lines.fail("expected the face count");
  const Location header_line = lines.where();

  MeshBuilder builder(limits, MeshFormat::Off);
  if (nv < 0 || nf < 0) lines.fail("negative counts in the header (" + std::to_string(nv) + " vertices, " + std::to_string(nf) + " faces)");
  // Minimum record sizes: "0 0 0\n" (6 bytes) per vertex, "3 0 0 0\n" (8) per face.
  builder.expect_vertices(nv, static_cast<std::int64_t>(lines.remaining() / 6));
  builder.expect_polygons(nf, static_cast<std::int64_t>(lines.remaining() / 8));

  for (std::int64_t i = 0; i < nv; ++i) {
    if (!next_data_line(lines, line))
      throw_parse_error(MeshFormat::Off, {lines.line_number() + 1, -1},
                        "the file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices declared on line " +
                            std::to_string(header_line.line));
    Tokens tokens(line);
    double xyz[3];
    for (double& c : xyz) {
      if (!tokens.next(token)) lines.fail("vertex " + std::to_string(i) + " has fewer than 3 coordinates");
      if (!parse_double(token, c)) lines.fail("malformed coordinate \"" + std::string(token.substr(0, 40)) + "\" of vertex " + std::to_string(i));
    }
    builder.add_vertex(xyz[0], xyz[1], xyz[2], lines.where());
  }

  std::vector<std::int64_t> corners;
  for (std::int64_t i = 0; i < nf; ++i) {
    if (!next_data_line(lines, line))
      throw_parse_error(MeshFormat::Off, {lines.line_number() + 1, -1},
                        "the file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " faces declared on line " +
                            std::to_string(header_line.line));
    Tokens tokens(line);
    std::int64_t n = 0;
    if (!tokens.next(token) || !parse_int64(token, n)) lines.fail("malformed corner count \"" + std::string(token.substr(0, 40)) + "\" of face " + std::to_string(i));
    builder.check_polygon_size(n, lines.where());
    corners.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      std::int64_t index = 0;
      if (!tokens.next(token)) lines.fail("face " + std::to_string(i) + " lists fewer than its " + std::to_string(n) + " corners");
      if (!parse_int64(token, index)) lines.fail("malformed vertex index \"" + std::string(token.substr(0, 40)) + "\" in face " + std::to_string(i));
      corners.push_back(index);
    }
    builder.add_polygon(corners, lines.where());
  }

  ReadResult result;
  result.encoding = MeshEncoding::Ascii;
  result.mesh = builder.finish(result.notes);
  if (next_data_line(lines, line))
    result.notes.push_back("ignored content after the " + with_commas(nf) + " declared faces, from line " + std::to_string(lines.line_number()));
  return result;
}

}  // namespace wish::io_detail
