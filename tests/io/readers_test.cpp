// Format-specific reading: OBJ index forms, PLY types/encodings/extra elements, OFF variants, STL both encodings,
// and content-based format detection.
#include <bit>
#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/io/volume_io.hpp"

namespace wish {
namespace {

ReadResult read(const std::string& bytes, MeshFormat hint = MeshFormat::Unknown) {
  ReadOptions options;
  options.hint = hint;
  return read_mesh(bytes, options);
}

TEST(ObjReader, IndexFormsNegativeIndicesAndPolygons) {
  const std::string obj =
      "# comment\n"
      "mtllib x.mtl\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "vt 0 0\nvn 0 0 1\n"
      "g group\n"
      "f 1/1/1 2/1/1 3/1/1\n"   // v/vt/vn
      "f 1//1 3//1 4//1\n"      // v//vn
      "f -4/1 -2/1 -1/1\n"      // negative: relative to the 4 vertices so far
      "f 1 2 3 4\n";            // quad -> 2 triangles
  const ReadResult r = read(obj);
  EXPECT_EQ(r.format, MeshFormat::Obj);
  ASSERT_EQ(r.mesh.vertex_count(), 4);
  ASSERT_EQ(r.mesh.face_count(), 5);
  EXPECT_EQ(r.mesh.faces.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(r.mesh.faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(r.mesh.faces.row(2), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(r.mesh.faces.row(3), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(r.mesh.faces.row(4), Eigen::RowVector3i(0, 2, 3));
  ASSERT_GE(r.notes.size(), 2u);  // triangulation and ignored statements are both reported
}

TEST(ObjReader, CrLfAndNoFinalNewline) {
  const ReadResult r = read("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3");
  EXPECT_EQ(r.mesh.face_count(), 1);
  EXPECT_EQ(r.mesh.vertices(1, 0), 1.0);
}

TEST(ObjReader, ZeroIndexIsAParseErrorWithLine) {
  try {
    read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "parse_error");
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("line")), 4);
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos);
  }
}

TEST(OffReader, VariantsCommentsAndCountsOnHeaderLine) {
  const std::string plain = "OFF\n# a comment\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  EXPECT_EQ(read(plain).mesh.face_count(), 4);
  const std::string coff = "COFF 4 4 6\n0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n0 1 0 1 1 1 1\n0 0 1 1 1 1 1\n"
                           "3 0 2 1 0.5 0.5 0.5\n3 0 1 3\n3 0 3 2  # comment\n3 1 2 3\n";
  const ReadResult r = read(coff);
  EXPECT_EQ(r.format, MeshFormat::Off);
  EXPECT_EQ(r.mesh.vertex_count(), 4);
  EXPECT_EQ(r.mesh.face_count(), 4);
  const std::string noff = "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n";
  EXPECT_EQ(read(noff).mesh.face_count(), 1);
}

TEST(OffReader, FourDimensionalOffIsUnsupported) {
  try {
    read("4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n");
    FAIL();
  } catch (const WishError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::UnsupportedFormat);
  }
}

// Serialises one PLY value of a given type name in the given byte order.
void put(std::string& out, const std::string& type, double value, bool big) {
  auto raw = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof v);
    out.append(b, sizeof v);
  };
  if (type == "char") raw(static_cast<std::int8_t>(value));
  else if (type == "uchar") raw(static_cast<std::uint8_t>(value));
  else if (type == "short") raw(static_cast<std::int16_t>(value));
  else if (type == "ushort") raw(static_cast<std::uint16_t>(value));
  else if (type == "int") raw(static_cast<std::int32_t>(value));
  else if (type == "uint") raw(static_cast<std::uint32_t>(value));
  else if (type == "float") raw(static_cast<float>(value));
  else raw(value);
}

// A tetrahedron with odd types, extra properties before/after x y z, an extra element with lists in between,
// and the face list called vertex_index with a ushort count type.
std::string odd_ply(const std::string& encoding) {
  const bool ascii = encoding == "ascii", big = encoding == "binary_big_endian";
  std::string out = "ply\nformat " + encoding + " 1.0\ncomment odd\nobj_info x\n"
                    "element vertex 4\nproperty uchar red\nproperty short x\nproperty double y\nproperty list uchar int junk\n"
                    "property float z\nproperty uint flags\n"
                    "element material 2\nproperty list uint float coefficients\nproperty char id\n"
                    "element face 4\nproperty int before\nproperty list ushort uint vertex_index\nproperty double after\n"
                    "element trailer 3\nproperty double a\nproperty int b\nend_header\n";
  const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  auto emit = [&](const std::string& type, double value) {
    if (ascii) out += std::to_string(value) + " ";
    else put(out, type, value, big);
  };
  for (const auto& p : v) {
    emit("uchar", 200); emit("short", p[0]); emit("double", p[1]);
    emit("uchar", 2); emit("int", 7); emit("int", 8);
    emit("float", p[2]); emit("uint", 4000000000.0);
    if (ascii) out += "\n";
  }
  for (int m = 0; m < 2; ++m) {
    emit("uint", 3); emit("float", 1.5); emit("float", 2.5); emit("float", 3.5); emit("char", -3);
    if (ascii) out += "\n";
  }
  for (const auto& t : f) {
    emit("int", -1); emit("ushort", 3);
    for (int k : t) emit("uint", k);
    emit("double", 0.25);
    if (ascii) out += "\n";
  }
  for (int i = 0; i < 3; ++i) { emit("double", 1); emit("int", 2); if (ascii) out += "\n"; }
  return out;
}

TEST(PlyReader, AllEncodingsWithOddTypesAndExtraElements) {
  for (const std::string encoding : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(encoding);
    const ReadResult r = read(odd_ply(encoding));
    EXPECT_EQ(r.format, MeshFormat::Ply);
    ASSERT_EQ(r.mesh.vertex_count(), 4);
    ASSERT_EQ(r.mesh.face_count(), 4);
    EXPECT_EQ(r.mesh.vertices.row(3), Eigen::RowVector3d(0, 0, 1));
    EXPECT_EQ(r.mesh.vertices.row(1), Eigen::RowVector3d(1, 0, 0));
    EXPECT_EQ(r.mesh.faces.row(3), Eigen::RowVector3i(1, 2, 3));
  }
  EXPECT_EQ(read(odd_ply("binary_big_endian")).encoding, MeshEncoding::BinaryBigEndian);
  EXPECT_EQ(read(odd_ply("binary_little_endian")).encoding, MeshEncoding::BinaryLittleEndian);
}

TEST(PlyReader, TruncatedBinaryReportsByteOffset) {
  std::string ply = odd_ply("binary_little_endian");
  ply.resize(ply.size() - 60);  // cuts into the faces
  try {
    read(ply);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "parse_error");
    EXPECT_TRUE(e.details().count("byte_offset"));
  }
}

std::string binary_stl(const std::string& header80, int triangles) {
  std::string out = header80;
  out.resize(80, ' ');
  const std::uint32_t n = static_cast<std::uint32_t>(triangles);
  out.append(reinterpret_cast<const char*>(&n), 4);  // the test machines are little endian, as STL
  const float tri[4][3] = {{0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};  // normal + 3 corners
  for (int t = 0; t < triangles; ++t) {
    out.append(reinterpret_cast<const char*>(tri), sizeof tri);
    out.append(2, '\0');
  }
  return out;
}

TEST(StlReader, BinaryStartingWithSolidIsDetectedBySize) {
  const ReadResult r = read(binary_stl("solid but actually binary", 2));
  EXPECT_EQ(r.format, MeshFormat::Stl);
  EXPECT_EQ(r.encoding, MeshEncoding::BinaryLittleEndian);
  EXPECT_EQ(r.mesh.vertex_count(), 3);  // 6 corners welded
  EXPECT_EQ(r.mesh.face_count(), 2);
}

TEST(StlReader, AsciiWithTwoSolidsWeldsCorners) {
  const std::string stl =
      "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid a\n"
      "solid b\n facet normal 0 0 1\n  outer loop\n   vertex -0 0 0\n   vertex 0 1 0\n   vertex 0 0 1\n  endloop\n endfacet\nendsolid b\n";
  const ReadResult r = read(stl);
  EXPECT_EQ(r.encoding, MeshEncoding::Ascii);
  EXPECT_EQ(r.mesh.vertex_count(), 4);  // -0 and 0 are the same position
  EXPECT_EQ(r.mesh.face_count(), 2);
}

TEST(FormatDetection, ContentWinsHintBreaksTies) {
  EXPECT_EQ(detect_format("ply\nformat ascii 1.0\n", MeshFormat::Obj), MeshFormat::Ply);
  EXPECT_EQ(detect_format("OFF\n3 1 0\n"), MeshFormat::Off);
  EXPECT_EQ(detect_format("# c\nv 1 2 3\n"), MeshFormat::Obj);
  EXPECT_EQ(detect_format("solid x\nfacet normal 0 0 1\n"), MeshFormat::Stl);
  EXPECT_EQ(detect_format("hello world"), MeshFormat::Unknown);
  EXPECT_EQ(detect_format(binary_stl("x", 1)), MeshFormat::Stl);
  EXPECT_EQ(format_from_name(".OBJ"), MeshFormat::Obj);
  EXPECT_EQ(format_from_name("model/stl"), MeshFormat::Stl);
  EXPECT_EQ(format_from_name("application/ply"), MeshFormat::Ply);
  EXPECT_EQ(format_from_name("mesh.off"), MeshFormat::Off);
  EXPECT_EQ(format_from_name("txt"), MeshFormat::Unknown);
}

TEST(FormatDetection, UnknownContentIsUnsupportedFormat) {
  try {
    read("this is not a mesh\n");
    FAIL();
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "unsupported_format");
    EXPECT_EQ(e.category(), ErrorCategory::UnsupportedFormat);
  }
}

}  // namespace
}  // namespace wish

// A file that is not there is an I/O failure (category io, code file_not_found), not malformed input: the service
// answers 500 for its own files, and the message names the path.
TEST(FileReaders, MissingFileIsAnIoErrorNamingThePath) {
  const std::filesystem::path missing = std::filesystem::temp_directory_path() / "wish-no-such-file-3f9a.obj";
  std::filesystem::remove(missing);
  for (int which = 0; which < 2; ++which) {
    try {
      if (which == 0)
        (void)wish::read_mesh_file(missing);
      else
        (void)wish::read_volume_file(missing);
      FAIL() << "reading a missing file did not throw";
    } catch (const wish::WishError& e) {
      EXPECT_EQ(e.category(), wish::ErrorCategory::Io);
      EXPECT_EQ(e.code(), "file_not_found");
      EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    }
  }
}
