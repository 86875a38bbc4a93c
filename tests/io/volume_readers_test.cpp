// Label-volume readers: NIfTI-1 and TIFF round trips for every supported voxel type (written here: NIfTI by
// write_nifti, TIFF by libtiff), byte order, gzip, spacing metadata, and malformed or hostile headers refused with
// the check that failed.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <tiffio.h>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"

namespace wish {
namespace {

volume::LabelImage small_image() {
  volume::LabelImage image;
  image.dims = {5, 4, 3};
  image.spacing = Eigen::Vector3d(0.5, 0.25, 2.0);
  image.unit = "um";
  image.labels.resize(60);
  for (std::size_t i = 0; i < 60; ++i) image.labels[i] = static_cast<std::uint32_t>((i * 7) % 11);
  return image;
}

std::string error_code(const std::string& bytes, const VolumeReadOptions& options = {}) {
  try {
    read_volume(bytes, options);
  } catch (const WishError& e) {
    return e.code();
  }
  return "none";
}

TEST(NiftiReader, RoundTripsEveryDatatypeWithAndWithoutGzip) {
  const auto image = small_image();
  for (const char* type : {"uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"})
    for (bool gz : {false, true}) {
      const VolumeReadResult r = read_volume(write_nifti(image, type, gz));
      EXPECT_EQ(r.format, VolumeFormat::Nifti);
      EXPECT_EQ(r.datatype, type);
      EXPECT_EQ(r.image.dims, image.dims);
      EXPECT_EQ(r.image.labels, image.labels) << type << (gz ? " gz" : "");
      EXPECT_TRUE(r.image.spacing.isApprox(image.spacing, 1e-6));
      EXPECT_EQ(r.image.unit, "um");
      EXPECT_TRUE(r.spacing_from_file);
    }
}

TEST(NiftiReader, ReadsBigEndianFiles) {
  const auto image = small_image();
  std::string le = write_nifti(image, "int16");
  std::string be = le;
  auto swap = [&](std::size_t offset, int size) { std::reverse(be.begin() + static_cast<long>(offset), be.begin() + static_cast<long>(offset) + size); };
  swap(0, 4);
  for (int k = 0; k < 8; ++k) swap(40 + 2 * k, 2);
  swap(70, 2);
  swap(72, 2);
  for (int k = 0; k < 8; ++k) swap(76 + 4 * k, 4);
  swap(108, 4);
  swap(112, 4);
  swap(116, 4);
  for (std::size_t i = 0; i < 60; ++i) swap(352 + 2 * i, 2);
  const VolumeReadResult r = read_volume(be);
  EXPECT_EQ(r.image.labels, image.labels);
  EXPECT_TRUE(r.image.spacing.isApprox(image.spacing, 1e-6));
}

TEST(NiftiReader, SpacingOverrideAndUnit) {
  VolumeReadOptions options;
  options.spacing_override = Eigen::Vector3d(16, 16, 15);
  options.unit_override = "nm";
  const VolumeReadResult r = read_volume(write_nifti(small_image(), "uint8"), options);
  EXPECT_TRUE(r.image.spacing.isApprox(Eigen::Vector3d(16, 16, 15)));
  EXPECT_EQ(r.image.unit, "nm");
  options.spacing_override = Eigen::Vector3d(16, 0, 15);
  EXPECT_EQ(error_code(write_nifti(small_image(), "uint8"), options), "invalid_parameter");
}

TEST(NiftiReader, MalformedHeadersAreRefusedWithTheCheckThatFailed) {
  const std::string good = write_nifti(small_image(), "int16");
  std::string bad = good;
  bad[0] = 7;
  EXPECT_EQ(error_code(bad), "parse_error");  // sizeof_hdr
  EXPECT_EQ(error_code(good.substr(0, good.size() - 10)), "parse_error");  // truncated data
  bad = good;
  const std::int16_t four_d[2] = {4, 0};
  std::memcpy(bad.data() + 40, &four_d[0], 2);
  const std::int16_t t = 5;
  std::memcpy(bad.data() + 48, &t, 2);  // dim[4] = 5
  EXPECT_EQ(error_code(bad), "parse_error");
  bad = good;
  const std::int16_t rgb = 128;
  std::memcpy(bad.data() + 70, &rgb, 2);
  EXPECT_EQ(error_code(bad), "unsupported_datatype");
  bad = good;
  const std::int16_t wrong_bits = 8;
  std::memcpy(bad.data() + 72, &wrong_bits, 2);
  EXPECT_EQ(error_code(bad), "parse_error");
  // A header that declares 30000^3 voxels is refused before anything is allocated.
  bad = good;
  const std::int16_t huge = 30000;
  for (int k = 1; k <= 3; ++k) std::memcpy(bad.data() + 40 + 2 * k, &huge, 2);
  EXPECT_EQ(error_code(bad), "limit_exceeded");
  VolumeReadOptions small;
  small.limits.max_voxels = 59;
  EXPECT_EQ(error_code(good, small), "limit_exceeded");
  small = {};
  small.limits.max_bytes = 100;
  EXPECT_EQ(error_code(good, small), "limit_exceeded");
  // Corrupt gzip and not-a-volume.
  std::string gz = write_nifti(small_image(), "int16", true);
  for (std::size_t i = 20; i < gz.size() - 8; ++i) gz[i] = static_cast<char>(gz[i] ^ 0x5a);
  EXPECT_EQ(error_code(gz), "parse_error");
  EXPECT_EQ(error_code("ply\nformat ascii 1.0\n"), "unsupported_format");
}

TEST(NiftiReader, NonLabelValuesAreRefused) {
  auto image = small_image();
  std::string bytes = write_nifti(image, "float32");
  const float half = 2.5f, negative = -1.0f;
  std::memcpy(bytes.data() + 352 + 4 * 7, &half, 4);
  EXPECT_EQ(error_code(bytes), "invalid_label");
  bytes = write_nifti(image, "float32");
  std::memcpy(bytes.data() + 352, &negative, 4);
  EXPECT_EQ(error_code(bytes), "invalid_label");
  bytes = write_nifti(image, "int16");
  const std::int16_t minus = -3;
  std::memcpy(bytes.data() + 352 + 2, &minus, 2);
  try {
    read_volume(bytes);
    FAIL() << "negative label accepted";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "invalid_label");
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("voxel")), 1);
  }
}

TEST(NiftiReader, FloatsInZeroToOneThatAreNotIntegersAreReadAsAProbabilityMap) {
  volume::LabelImage map = small_image();
  map.probability_scale = volume::LabelImage::kProbabilityScale;
  const double ps[] = {0, 0.25, 0.5, 0.75, 1, 0.125};
  for (std::size_t i = 0; i < map.labels.size(); ++i)
    map.labels[i] = static_cast<std::uint32_t>(ps[i % 6] * volume::LabelImage::kProbabilityScale);
  for (const char* type : {"float32", "float64"}) {
    const VolumeReadResult r = read_volume(write_nifti(map, type, true));
    EXPECT_EQ(r.image.probability_scale, volume::LabelImage::kProbabilityScale);
    EXPECT_EQ(r.image.labels, map.labels) << type;  // these probabilities are exact in fixed point
    ASSERT_FALSE(r.notes.empty());
    EXPECT_NE(r.notes.back().find("probability map"), std::string::npos);
  }
  // Integer floats stay labels; a probability map with a value above 1 is refused with the voxel.
  EXPECT_EQ(read_volume(write_nifti(small_image(), "float32")).image.probability_scale, 0u);
  std::string bytes = write_nifti(map, "float32");
  const float above = 1.5f;
  std::memcpy(bytes.data() + 352 + 4 * 4, &above, 4);
  try {
    read_volume(bytes);
    FAIL() << "1.5 accepted in a probability map";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "invalid_label");
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("voxel")), 4);
  }
}

// Writes a multi-page TIFF with libtiff (one page per z slice) and returns its bytes.
template <typename T>
std::string write_tiff(const volume::LabelImage& image, int sample_format, const std::string& description, bool tiled = false) {
  const auto path = std::filesystem::temp_directory_path() / ("wish_volume_test_" + std::to_string(::getpid()) + ".tif");
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  EXPECT_NE(tif, nullptr);
  for (std::int64_t z = 0; z < image.dims[2]; ++z) {
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(image.dims[0]));
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(image.dims[1]));
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, static_cast<std::uint16_t>(8 * sizeof(T)));
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(1));
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, static_cast<std::uint16_t>(sample_format));
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    if (!description.empty()) TIFFSetField(tif, TIFFTAG_IMAGEDESCRIPTION, description.c_str());
    TIFFSetField(tif, TIFFTAG_XRESOLUTION, static_cast<float>(1.0 / image.spacing(0)));
    TIFFSetField(tif, TIFFTAG_YRESOLUTION, static_cast<float>(1.0 / image.spacing(1)));
    TIFFSetField(tif, TIFFTAG_RESOLUTIONUNIT, RESUNIT_NONE);
    std::vector<T> plane(static_cast<std::size_t>(image.dims[0] * image.dims[1]));
    for (std::size_t i = 0; i < plane.size(); ++i) {
      const double v = image.labels[static_cast<std::size_t>(z) * plane.size() + i];
      plane[i] = static_cast<T>(image.probability_scale > 0 ? v / image.probability_scale : v);  // a probability map: p
    }
    if (tiled) {
      TIFFSetField(tif, TIFFTAG_TILEWIDTH, 16u);
      TIFFSetField(tif, TIFFTAG_TILELENGTH, 16u);
      std::vector<T> tile(256, 0);
      for (std::int64_t ty = 0; ty < image.dims[1]; ty += 16)
        for (std::int64_t tx = 0; tx < image.dims[0]; tx += 16) {
          std::fill(tile.begin(), tile.end(), T(0));
          for (std::int64_t y = ty; y < std::min<std::int64_t>(ty + 16, image.dims[1]); ++y)
            for (std::int64_t x = tx; x < std::min<std::int64_t>(tx + 16, image.dims[0]); ++x)
              tile[static_cast<std::size_t>((y - ty) * 16 + (x - tx))] = plane[static_cast<std::size_t>(y * image.dims[0] + x)];
          TIFFWriteTile(tif, tile.data(), static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty), 0, 0);
        }
    } else {
      for (std::int64_t y = 0; y < image.dims[1]; ++y)
        TIFFWriteScanline(tif, plane.data() + y * image.dims[0], static_cast<std::uint32_t>(y), 0);
    }
    TIFFWriteDirectory(tif);
  }
  TIFFClose(tif);
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::filesystem::remove(path);
  return ss.str();
}

TEST(TiffReader, RoundTripsStacksWithImageJSpacing) {
  const auto image = small_image();
  const std::string imagej = "ImageJ=1.54f\nimages=3\nslices=3\nunit=micron\nspacing=2.0\n";
  const VolumeReadResult r8 = read_volume(write_tiff<std::uint8_t>(image, SAMPLEFORMAT_UINT, imagej));
  EXPECT_EQ(r8.format, VolumeFormat::Tiff);
  EXPECT_EQ(r8.datatype, "uint8");
  EXPECT_EQ(r8.image.dims, image.dims);
  EXPECT_EQ(r8.image.labels, image.labels);
  EXPECT_TRUE(r8.image.spacing.isApprox(image.spacing, 1e-6)) << r8.image.spacing.transpose();
  EXPECT_EQ(r8.image.unit, "um");
  EXPECT_EQ(read_volume(write_tiff<std::uint16_t>(image, SAMPLEFORMAT_UINT, imagej)).image.labels, image.labels);
  EXPECT_EQ(read_volume(write_tiff<std::int32_t>(image, SAMPLEFORMAT_INT, imagej)).image.labels, image.labels);
  EXPECT_EQ(read_volume(write_tiff<float>(image, SAMPLEFORMAT_IEEEFP, imagej)).image.labels, image.labels);
  EXPECT_EQ(read_volume(write_tiff<std::uint32_t>(image, SAMPLEFORMAT_UINT, imagej, /*tiled=*/true)).image.labels, image.labels);
  // A float probability map, stripped and tiled.
  volume::LabelImage map = image;
  map.probability_scale = volume::LabelImage::kProbabilityScale;
  for (std::size_t i = 0; i < map.labels.size(); ++i) map.labels[i] = static_cast<std::uint32_t>((i % 5) * (map.probability_scale / 4));
  for (bool tiled : {false, true}) {
    const VolumeReadResult p = read_volume(write_tiff<float>(map, SAMPLEFORMAT_IEEEFP, "", tiled));
    EXPECT_EQ(p.image.probability_scale, map.probability_scale);
    EXPECT_EQ(p.image.labels, map.labels);
  }
}

TEST(TiffReader, OmeXmlSpacing) {
  const std::string ome = "<?xml version=\"1.0\"?><OME><Image><Pixels PhysicalSizeX=\"16\" PhysicalSizeXUnit=\"nm\" "
                          "PhysicalSizeY=\"16\" PhysicalSizeYUnit=\"nm\" PhysicalSizeZ=\"15\" PhysicalSizeZUnit=\"nm\"/></Image></OME>";
  const VolumeReadResult r = read_volume(write_tiff<std::uint16_t>(small_image(), SAMPLEFORMAT_UINT, ome));
  EXPECT_TRUE(r.image.spacing.isApprox(Eigen::Vector3d(16, 16, 15)));
  EXPECT_EQ(r.image.unit, "nm");
  EXPECT_TRUE(r.spacing_from_file);
}

TEST(TiffReader, HostileInputIsRefused) {
  const std::string good = write_tiff<std::uint16_t>(small_image(), SAMPLEFORMAT_UINT, "");
  EXPECT_EQ(error_code(good.substr(0, 8)), "parse_error");
  EXPECT_EQ(error_code(good.substr(0, good.size() / 2)), "parse_error");
  VolumeReadOptions small;
  small.limits.max_voxels = 59;
  EXPECT_EQ(error_code(good, small), "limit_exceeded");
  small = {};
  small.limits.max_pages = 2;
  EXPECT_EQ(error_code(good, small), "limit_exceeded");
  EXPECT_EQ(error_code(write_tiff<double>(small_image(), SAMPLEFORMAT_COMPLEXIEEEFP, "")), "unsupported_datatype");
}

}  // namespace
}  // namespace wish
