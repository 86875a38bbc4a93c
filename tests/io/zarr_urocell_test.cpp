// UroCell as OME-Zarr (../shared/data/urocell, skipped when absent; suite named Slow* so the sanitizer run skips it):
// every volume is written as an OME-Zarr store by Debian's python3-zarr (tests/testing/ome_zarr_writer.py, an
// independent writer: numpy reads the NIfTI, zarr chunks and compresses it), one compressor per volume in turn (zlib,
// gzip, zstd, blosc lz4, blosc zstd), the first of each class also as a ZipStore zip. The store must read back as the
// NIfTI original: same dims, voxel size and every label, hence the same objects (count, ids, voxels per object).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include "core/io/volume_io.hpp"
#include "core/volume/label_objects.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

namespace fs = std::filesystem;

bool write_store(const fs::path& nifti, const fs::path& out, const std::string& codec, bool zip) {
  const std::string cmd = "PYTHONPATH= /usr/bin/python3 " + (fs::path(WISH_TEST_SOURCE_DIR) / "testing/ome_zarr_writer.py").string() +
                          " " + nifti.string() + " " + out.string() + " " + codec + (zip ? " zip" : "") + " 2>&1";
  return std::system(cmd.c_str()) == 0;
}

bool have_python_zarr() { return std::system("/usr/bin/python3 -c 'import zarr, numcodecs' >/dev/null 2>&1") == 0; }

TEST(SlowUroCellZarr, EveryVolumeAsOmeZarrFindsTheObjectsOfItsNifti) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const fs::path root = *wish::testing::shared_data_dir() / "urocell";
  if (!fs::exists(root)) GTEST_SKIP() << "urocell absent";
  ASSERT_TRUE(have_python_zarr()) << "python3-zarr (scripts/install-deps.sh --test) is needed to write the stores";
  const fs::path tmp = fs::temp_directory_path() / ("wish_zarr_urocell_" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  const char* codecs[] = {"zlib", "gzip", "zstd", "blosc", "blosc-zstd"};
  int volumes = 0, objects = 0;
  for (const char* sub : {"mito/instance", "lyso/binary", "fv/instance"}) {
    bool first = true;
    for (const auto& f : wish::testing::files_in(root / sub, {".gz"})) {
      const std::string codec = codecs[volumes % 5];
      const fs::path store = tmp / (f.stem().stem().string() + "-" + codec + (first ? ".zarr.zip" : ".zarr"));
      ASSERT_TRUE(write_store(f, store, codec, first)) << f;
      const VolumeReadResult nifti = read_volume_file(f);
      const VolumeReadResult zarr = read_volume_file(store);
      EXPECT_EQ(zarr.format, VolumeFormat::OmeZarr);
      EXPECT_EQ(zarr.image.dims, nifti.image.dims) << store;
      EXPECT_TRUE(zarr.image.spacing.isApprox(nifti.image.spacing, 1e-12)) << store;
      EXPECT_EQ(zarr.image.unit, nifti.image.unit) << store;
      EXPECT_TRUE(zarr.image.labels == nifti.image.labels) << store << ": labels differ";
      const volume::ObjectSet a = volume::find_objects(nifti.image, {});
      const volume::ObjectSet b = volume::find_objects(zarr.image, {});
      ASSERT_EQ(a.objects.size(), b.objects.size()) << store;
      for (std::size_t i = 0; i < a.objects.size(); ++i) {
        EXPECT_EQ(a.objects[i].id, b.objects[i].id);
        EXPECT_EQ(a.objects[i].voxel_count, b.objects[i].voxel_count);
      }
      std::printf("%s/%s (%s%s): %zu objects, same as the NIfTI\n", sub, f.filename().c_str(), codec.c_str(),
                  first ? ", zip" : "", b.objects.size());
      ++volumes;
      objects += static_cast<int>(b.objects.size());
      first = false;
      fs::remove_all(store);
    }
  }
  fs::remove_all(tmp);
  EXPECT_GT(volumes, 0);
  std::printf("%d UroCell volumes, %d objects: identical through OME-Zarr\n", volumes, objects);
}

}  // namespace
}  // namespace wish
