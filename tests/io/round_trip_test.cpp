// write -> read gives the same mesh, for every format and encoding, and via files.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

// Coordinates made exactly representable as float, so binary STL (float32) round-trips exactly too; STL welds by
// position, which for this mesh (no coincident vertices, all referenced) keeps vertices but may renumber them.
Mesh test_mesh() {
  Mesh mesh = testing::make_ellipsoid(1.5, 1.0, 0.75, 2);
  mesh.vertices = mesh.vertices.cast<float>().cast<double>();
  return mesh;
}

// Same triangles with the same corner positions, in the same order.
void expect_same_geometry(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.face_count(), b.face_count());
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  for (Eigen::Index f = 0; f < a.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(a.vertices.row(a.faces(f, k)), b.vertices.row(b.faces(f, k))) << "face " << f << " corner " << k;
}

struct Case {
  MeshFormat format;
  MeshEncoding encoding;
};

TEST(RoundTrip, EveryFormatAndEncoding) {
  const Mesh mesh = test_mesh();
  for (const Case c : {Case{MeshFormat::Obj, MeshEncoding::Ascii}, Case{MeshFormat::Off, MeshEncoding::Ascii},
                       Case{MeshFormat::Ply, MeshEncoding::Ascii}, Case{MeshFormat::Ply, MeshEncoding::BinaryLittleEndian},
                       Case{MeshFormat::Ply, MeshEncoding::BinaryBigEndian}, Case{MeshFormat::Stl, MeshEncoding::Ascii},
                       Case{MeshFormat::Stl, MeshEncoding::BinaryLittleEndian}}) {
    SCOPED_TRACE(std::string(to_string(c.format)) + " encoding " + std::to_string(static_cast<int>(c.encoding)));
    const std::string bytes = write_mesh(mesh, c.format, c.encoding);
    const ReadResult r = read_mesh(bytes);
    EXPECT_EQ(r.format, c.format);
    EXPECT_EQ(r.encoding, c.encoding);
    if (c.format == MeshFormat::Stl) {
      expect_same_geometry(mesh, r.mesh);
    } else {
      EXPECT_EQ(r.mesh.vertices, mesh.vertices);
      EXPECT_EQ(r.mesh.faces, mesh.faces);
    }
  }
}

TEST(RoundTrip, TextFormatsAreExactForArbitraryDoubles) {
  Mesh mesh = testing::make_ellipsoid(1.0 / 3.0, 2.0 / 7.0, 1e-300, 1);
  mesh.vertices.col(0).array() += 12345.678901234567;
  for (const Case c : {Case{MeshFormat::Obj, MeshEncoding::Ascii}, Case{MeshFormat::Off, MeshEncoding::Ascii},
                       Case{MeshFormat::Ply, MeshEncoding::Ascii}, Case{MeshFormat::Ply, MeshEncoding::BinaryBigEndian}}) {
    const ReadResult r = read_mesh(write_mesh(mesh, c.format, c.encoding));
    EXPECT_EQ(r.mesh.vertices, mesh.vertices) << to_string(c.format);
    EXPECT_EQ(r.mesh.faces, mesh.faces);
  }
}

TEST(RoundTrip, Files) {
  const Mesh mesh = test_mesh();
  const auto dir = std::filesystem::temp_directory_path() / ("wish_io_round_trip_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"m.obj", "m.off", "m.ply", "m.stl"}) {
    write_mesh_file(mesh, dir / name);
    const ReadResult r = read_mesh_file(dir / name);
    EXPECT_EQ(r.format, format_from_name(name));
    expect_same_geometry(mesh, r.mesh);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace wish
