// Hand-made hostile inputs: each is refused with the documented code and a position, quickly and without
// allocating what the header claims.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"

namespace wish {
namespace {

// Reads and returns the error (fails the test when nothing is thrown).
WishError refusal(const std::string& bytes, ReadOptions options = {}) {
  try {
    read_mesh(bytes, options);
  } catch (const WishError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << bytes.substr(0, 80);
  return WishError(ErrorCategory::Internal, "none", "none");
}

// Refused by the limit, not by the allocator: reserving 1e12 faces first would end in std::bad_alloc (another
// error) or in gigabytes touched, never in limit_exceeded naming the header's count.
TEST(HostileInput, HeaderClaimingTrillionFacesIsALimitBeforeAllocation) {
  for (const std::string& bytes : {std::string("OFF\n3 1000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                                   std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement face 1000000000000\nproperty list uchar int vertex_indices\n"
                                               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                                   std::string("ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
                                               "property float y\nproperty float z\nend_header\n")}) {
    const WishError e = refusal(bytes);
    EXPECT_EQ(e.code(), "limit_exceeded") << e.what();
    EXPECT_EQ(e.category(), ErrorCategory::TooLarge);
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("value")), 1000000000000);
  }
}

TEST(HostileInput, BinaryStlClaimingMoreTrianglesThanLimit) {
  std::string stl(80, 'x');
  const std::uint32_t n = 4'000'000'000u;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  stl.append(100, '\0');
  ReadOptions options;
  options.hint = MeshFormat::Stl;
  EXPECT_EQ(refusal(stl, options).code(), "limit_exceeded");
}

TEST(HostileInput, TruncatedBinaryStl) {
  std::string stl(80, 'x');
  const std::uint32_t n = 10;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  stl.append(50 * 3 + 7, '\1');  // 3 and a bit of the 10 declared triangles
  ReadOptions options;
  options.hint = MeshFormat::Stl;
  const WishError e = refusal(stl, options);
  EXPECT_EQ(e.code(), "parse_error") << e.what();
  EXPECT_TRUE(e.details().count("byte_offset"));
  // Also when the header starts with "solid": it is binary content all the same.
  stl.replace(0, 5, "solid");
  EXPECT_EQ(refusal(stl).code(), "parse_error");
}

TEST(HostileInput, TruncatedBinaryPly) {
  std::string ply = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                    "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::size_t header = ply.size();
  ply.append(3 * 24, '\0');
  ply += '\3';                // a triangle...
  ply.append(5, '\0');        // ...cut after 5 of its 12 index bytes
  const WishError e = refusal(ply);
  EXPECT_EQ(e.code(), "parse_error") << e.what();
  ASSERT_TRUE(e.details().count("byte_offset"));
  EXPECT_GE(std::get<std::int64_t>(e.details().at("byte_offset")), static_cast<std::int64_t>(header + 72));
  EXPECT_NE(std::string(e.what()).find("byte"), std::string::npos);
}

TEST(HostileInput, NonFiniteCoordinates) {
  for (const std::string& bytes : {std::string("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
                                   std::string("OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"),
                                   std::string("v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n")}) {
    const WishError e = refusal(bytes);
    EXPECT_EQ(e.code(), "non_finite_vertex") << e.what();
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("vertex")), 1);
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("line")), bytes[0] == 'O' ? 4 : 2);
  }
}

TEST(HostileInput, OutOfRangeAndNegativeIndices) {
  for (const std::string& bytes : {std::string("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -5\n"),
                                   std::string("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1000000000\n"),
                                   std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1000000000\n"),
                                   std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -5\n"),
                                   std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -5\n")}) {
    const WishError e = refusal(bytes);
    EXPECT_EQ(e.code(), "index_out_of_range") << e.what();
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("vertex_count")), 3);
    EXPECT_TRUE(e.details().count("face"));
    EXPECT_TRUE(e.details().count("index"));
  }
}

TEST(HostileInput, TwoMegabyteLineIsALimit) {
  std::string obj = "v 0 0 0\n# " + std::string(2 << 20, 'x') + "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const WishError e = refusal(obj);
  EXPECT_EQ(e.code(), "limit_exceeded") << e.what();
  EXPECT_EQ(std::get<std::string>(e.details().at("limit")), "max_line_length");
}

TEST(HostileInput, LimitsAreConfigurable) {
  ReadOptions options;
  options.limits.max_vertices = 2;
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", options).code(), "limit_exceeded");
  options = {};
  options.limits.max_bytes = 10;
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", options).code(), "limit_exceeded");
  options = {};
  options.limits.max_polygon_vertices = 3;
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n", options).code(), "limit_exceeded");
  options = {};
  options.limits.max_faces = 1;
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n", options).code(), "limit_exceeded");
}

TEST(HostileInput, Utf16IsRefusedAsUnsupported) {
  const std::string text = "v 0 0 0\n";
  std::string utf16 = "\xFF\xFE";
  for (char c : text) { utf16 += c; utf16 += '\0'; }
  const WishError e = refusal(utf16);
  EXPECT_EQ(e.code(), "unsupported_format");
  EXPECT_NE(std::string(e.what()).find("UTF-16"), std::string::npos);
}

TEST(HostileInput, EmptyAndFaceless) {
  EXPECT_EQ(refusal("").code(), "empty_mesh");
  EXPECT_EQ(refusal("v 0 0 0\nv 1 0 0\n").code(), "empty_mesh");
  EXPECT_EQ(refusal("OFF\n0 0 0\n").code(), "empty_mesh");
}

TEST(HostileInput, TruncatedTextReportsLine) {
  const WishError e = refusal("OFF\n4 1 0\n0 0 0\n1 0 0\n");
  EXPECT_EQ(e.code(), "parse_error");
  EXPECT_EQ(std::get<std::int64_t>(e.details().at("line")), 5);
  EXPECT_EQ(refusal("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n").code(), "parse_error");
  EXPECT_EQ(refusal("OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n").code(), "parse_error");
}

TEST(HostileInput, HugeSkippedElementCounts) {
  // An unknown element of 10^15 rows without properties, and one of fixed-size rows that are not there.
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  std::string body(36, '\0');
  EXPECT_EQ(refusal(head + "element nothing 1000000000000000\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n" + body).code(),
            "empty_mesh");
  EXPECT_EQ(refusal(head + "element extra 1000000000000000\nproperty double a\nend_header\n" + body).code(), "parse_error");
}

}  // namespace
}  // namespace wish
