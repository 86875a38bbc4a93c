// Debian's assimp-testmodels hold deliberately odd and broken files: every one is either read or refused with a
// WishError; nothing crashes, hangs or throws anything else. Also checks a few that must be read correctly.
#include <chrono>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"

namespace wish {
namespace {

const std::filesystem::path kModels = "/usr/share/assimp/models";

TEST(AssimpModels, EveryFileIsReadOrRefusedWithWishError) {
  if (!std::filesystem::is_directory(kModels)) GTEST_SKIP() << kModels << " is absent (apt-get install assimp-testmodels)";
  int read = 0, refused = 0;
  for (const char* dir : {"OBJ", "OFF", "PLY", "STL", "invalid"}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(kModels / dir)) {
      if (!entry.is_regular_file()) continue;
      SCOPED_TRACE(entry.path().string());
      const auto start = std::chrono::steady_clock::now();
      try {
        const ReadResult r = read_mesh_file(entry.path());
        EXPECT_GT(r.mesh.face_count(), 0);
        EXPECT_GE(r.mesh.faces.minCoeff(), 0);
        EXPECT_LT(r.mesh.faces.maxCoeff(), r.mesh.vertex_count());
        ++read;
      } catch (const WishError& e) {
        EXPECT_FALSE(e.code().empty());
        EXPECT_NE(e.category(), ErrorCategory::Internal) << e.what();
        ++refused;
      }
      EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
    }
  }
  EXPECT_GT(read, 20);
  EXPECT_GT(refused, 5);
  std::cout << "assimp models: " << read << " read, " << refused << " refused\n";
}

TEST(AssimpModels, KnownFilesReadCorrectly) {
  if (!std::filesystem::is_directory(kModels)) GTEST_SKIP() << kModels << " is absent";
  const ReadResult cube = read_mesh_file(kModels / "PLY/cube_binary.ply");
  EXPECT_EQ(cube.mesh.vertex_count(), 8);
  EXPECT_EQ(cube.mesh.face_count(), 12);
  const ReadResult spider_ascii = read_mesh_file(kModels / "STL/Spider_ascii.stl");
  const ReadResult spider_binary = read_mesh_file(kModels / "STL/Spider_binary.stl");
  EXPECT_EQ(spider_ascii.encoding, MeshEncoding::Ascii);
  EXPECT_EQ(spider_binary.encoding, MeshEncoding::BinaryLittleEndian);
  EXPECT_EQ(spider_ascii.mesh.face_count(), spider_binary.mesh.face_count());
  EXPECT_EQ(spider_ascii.mesh.vertex_count(), spider_binary.mesh.vertex_count());
  EXPECT_EQ(read_mesh_file(kModels / "OFF/Cube.off").mesh.face_count(), 12);
  EXPECT_EQ(read_mesh_file(kModels / "OBJ/box.obj").mesh.face_count(), 12);
  // The header of invalid/OutOfMemory.off claims 353,535,235,358 vertices.
  try {
    read_mesh_file(kModels / "invalid/OutOfMemory.off");
    FAIL();
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "limit_exceeded");
  }
}

}  // namespace
}  // namespace wish
