// OME-Zarr label images (core/io/zarr_*): one small label image, known voxel by voxel, stored every way zarr v2 and
// NGFF allow (C and F order, axes in any order, size-1 t / c axes, both byte orders, every integer and float dtype,
// "." and "/" separators, edge chunks whose padding holds junk, missing chunks = fill_value, zlib), must read back
// identical; metadata picks the label image, the level, the voxel size (dataset scale x multiscale scale) and the unit;
// what cannot be read is refused with the check that failed, limits before any allocation. The stores are built here
// byte by byte (the independent writer, Debian's python3-zarr, is in tests/cli/test_zarr_inputs.py and
// tests/io/zarr_urocell_test.cpp).
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <zlib.h>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"
#include "core/io/zarr_store.hpp"

namespace wish {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Store = std::map<std::string, std::string>;

constexpr std::int64_t kNx = 5, kNy = 4, kNz = 3;

// The label at (x, y, z): background on a pattern, else 1..9.
std::uint32_t truth(std::int64_t x, std::int64_t y, std::int64_t z) {
  if ((x * 7 + y * 3 + z * 5) % 4 == 0) return 0;
  return static_cast<std::uint32_t>(1 + (x + 2 * y + 3 * z) % 9);
}

std::vector<std::uint32_t> truth_labels() {
  std::vector<std::uint32_t> v;
  for (std::int64_t z = 0; z < kNz; ++z)
    for (std::int64_t y = 0; y < kNy; ++y)
      for (std::int64_t x = 0; x < kNx; ++x) v.push_back(truth(x, y, z));
  return v;
}

struct Layout {
  std::string axes = "zyx";                 // one letter per zarr dimension; t, c have size 1
  std::vector<std::int64_t> chunks;         // per dimension; default 2 for space axes
  bool fortran = false;
  std::string dtype = "<u2";
  bool zlib = false;
  char separator = '.';
  bool skip_background_chunks = false;      // leave all-zero chunks out (fill_value 0)
  std::string prefix = "labels/cells/0/";
};

std::int64_t size_of(char axis) { return axis == 'x' ? kNx : axis == 'y' ? kNy : axis == 'z' ? kNz : 1; }

// One element of `dtype` holding `v`.
std::string encode(const std::string& dtype, double v) {
  const char kind = dtype[1];
  const int size = dtype[2] - '0';
  unsigned char b[8] = {};
  auto put = [&](auto value) { std::memcpy(b, &value, sizeof value); };
  if (kind == 'f') size == 4 ? put(static_cast<float>(v)) : put(v);
  else if (kind == 'i') size == 1 ? put(static_cast<std::int8_t>(v)) : size == 2 ? put(static_cast<std::int16_t>(v))
                      : size == 4 ? put(static_cast<std::int32_t>(v)) : put(static_cast<std::int64_t>(v));
  else size == 1 ? put(static_cast<std::uint8_t>(v)) : size == 2 ? put(static_cast<std::uint16_t>(v))
     : size == 4 ? put(static_cast<std::uint32_t>(v)) : put(static_cast<std::uint64_t>(v));
  const bool big = dtype[0] == '>';
  if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + size);
  return std::string(reinterpret_cast<char*>(b), static_cast<std::size_t>(size));
}

std::string zlib_compress(const std::string& raw) {
  uLongf n = compressBound(raw.size());
  std::string out(n, '\0');
  EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 6), Z_OK);
  out.resize(n);
  return out;
}

// The array's .zarray and chunks, for `layout`, into `store`.
void put_array(Store& store, const Layout& l) {
  const std::size_t nd = l.axes.size();
  std::vector<std::int64_t> shape(nd), chunks = l.chunks;
  for (std::size_t d = 0; d < nd; ++d) shape[d] = size_of(l.axes[d]);
  if (chunks.empty())
    for (std::size_t d = 0; d < nd; ++d) chunks.push_back(shape[d] == 1 ? 1 : 2);
  json za = {{"zarr_format", 2}, {"shape", shape}, {"chunks", chunks}, {"dtype", l.dtype},
             {"compressor", l.zlib ? json{{"id", "zlib"}, {"level", 6}} : json()}, {"fill_value", 0},
             {"order", l.fortran ? "F" : "C"}, {"filters", nullptr}, {"dimension_separator", std::string(1, l.separator)}};
  store[l.prefix + ".zarray"] = za.dump();
  std::vector<std::int64_t> grid(nd), g(nd, 0);
  std::int64_t chunk_count = 1, chunk_voxels = 1;
  for (std::size_t d = 0; d < nd; ++d) {
    grid[d] = (shape[d] + chunks[d] - 1) / chunks[d];
    chunk_count *= grid[d];
    chunk_voxels *= chunks[d];
  }
  for (std::int64_t c = 0; c < chunk_count; ++c) {
    std::string raw;
    bool any = false;
    std::vector<std::int64_t> e(nd, 0);  // element index within the chunk, in memory order
    for (std::int64_t k = 0; k < chunk_voxels; ++k) {
      std::int64_t rest = k;
      for (std::size_t j = 0; j < nd; ++j) {  // memory order: last dimension fastest (C) or first (F)
        const std::size_t d = l.fortran ? j : nd - 1 - j;
        e[d] = rest % chunks[d];
        rest /= chunks[d];
      }
      std::int64_t xyz[3] = {0, 0, 0};
      bool inside = true;
      for (std::size_t d = 0; d < nd; ++d) {
        const std::int64_t p = g[d] * chunks[d] + e[d];
        if (p >= shape[d]) inside = false;
        if (l.axes[d] == 'x') xyz[0] = p;
        if (l.axes[d] == 'y') xyz[1] = p;
        if (l.axes[d] == 'z') xyz[2] = p;
      }
      // Padding of edge chunks: junk a reader must not take as labels (100 is not in the image; -1 would be refused).
      const double v = inside ? truth(xyz[0], xyz[1], xyz[2]) : 100;
      any = any || (inside && v != 0);
      raw += encode(l.dtype, v);
    }
    std::string key = l.prefix;
    for (std::size_t d = 0; d < nd; ++d) {
      if (d) key += l.separator;
      key += std::to_string(g[d]);
    }
    if (any || !l.skip_background_chunks) store[key] = l.zlib ? zlib_compress(raw) : raw;
    for (std::size_t d = nd; d-- > 0;) {
      if (++g[d] < grid[d]) break;
      g[d] = 0;
    }
  }
}

json axes_json(const std::string& axes, const char* unit = "micrometer") {
  json a = json::array();
  for (char c : axes) {
    const std::string n(1, c);
    if (c == 't') a.push_back({{"name", n}, {"type", "time"}});
    else if (c == 'c') a.push_back({{"name", n}, {"type", "channel"}});
    else a.push_back({{"name", n}, {"type", "space"}, {"unit", unit}});
  }
  return a;
}

// A whole image store: root image (its own array, never read), labels/ listing `names`, label image "cells" with
// levels 0 and 1 (1 is a copy: only its scale differs), dataset scale s and multiscale scale 10.
Store image_store(const Layout& l, std::vector<std::string> names = {"cells"}) {
  Store s;
  s[".zgroup"] = R"({"zarr_format": 2})";
  json scale0 = json::array(), scale1 = json::array(), global = json::array();
  for (char c : l.axes) {
    const double v = c == 'x' ? 0.05 : c == 'y' ? 0.025 : c == 'z' ? 0.2 : 1.0;
    scale0.push_back(v);
    scale1.push_back(2 * v);
    global.push_back(c == 'x' || c == 'y' || c == 'z' ? 10.0 : 1.0);
  }
  json ms = {{"version", "0.4"}, {"axes", axes_json(l.axes)},
             {"datasets", {{{"path", "0"}, {"coordinateTransformations", {{{"type", "scale"}, {"scale", scale0}}}}},
                           {{"path", "1"}, {"coordinateTransformations", {{{"type", "scale"}, {"scale", scale1}}}}}}},
             {"coordinateTransformations", {{{"type", "scale"}, {"scale", global}}}}};
  s[".zattrs"] = json{{"multiscales", {ms}}}.dump();
  s["labels/.zgroup"] = s[".zgroup"];
  s["labels/.zattrs"] = json{{"labels", names}}.dump();
  s["labels/cells/.zgroup"] = s[".zgroup"];
  s["labels/cells/.zattrs"] = json{{"multiscales", {ms}}, {"image-label", {{"version", "0.4"}}}}.dump();
  put_array(s, l);
  Layout level1 = l;
  level1.prefix = "labels/cells/1/";
  put_array(s, level1);
  return s;
}

std::string zip_of(const Store& s) { return io_detail::write_zip({s.begin(), s.end()}); }

fs::path directory_of(const Store& s, const std::string& name) {
  const fs::path root = fs::temp_directory_path() / ("wish_zarr_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(root);
  for (const auto& [key, value] : s) {
    fs::create_directories((root / key).parent_path());
    std::ofstream(root / key, std::ios::binary) << value;
  }
  return root;
}

std::string error_code(const std::string& bytes, const VolumeReadOptions& options = {}) {
  try {
    read_volume(bytes, options);
  } catch (const WishError& e) {
    return e.code();
  }
  return "none";
}

void expect_truth(const VolumeReadResult& r, const std::string& what) {
  EXPECT_EQ(r.format, VolumeFormat::OmeZarr) << what;
  EXPECT_EQ(r.image.dims, (std::array<std::int64_t, 3>{kNx, kNy, kNz})) << what;
  EXPECT_EQ(r.image.labels, truth_labels()) << what;
}

TEST(ZarrReader, EveryLayoutOfOneImageReadsBackIdentical) {
  std::vector<Layout> layouts;
  for (std::string axes : {"zyx", "xyz", "yzx", "tczyx", "czyx", "zcyx"})
    for (bool fortran : {false, true}) {
      Layout l;
      l.axes = axes;
      l.fortran = fortran;
      layouts.push_back(l);
    }
  for (std::string dtype : {"|u1", "|i1", "<u2", ">u2", "<i2", ">i2", "<u4", ">i4", "<u8", ">i8", "<f4", ">f8"}) {
    Layout l;
    l.dtype = dtype;
    layouts.push_back(l);
  }
  Layout nested;
  nested.separator = '/';
  nested.zlib = true;
  nested.skip_background_chunks = true;
  nested.chunks = {1, 3, 2};
  layouts.push_back(nested);
  Layout one_chunk;
  one_chunk.chunks = {8, 8, 8};  // larger than the image: one chunk, mostly padding
  layouts.push_back(one_chunk);
  for (const Layout& l : layouts) {
    const std::string what = l.axes + (l.fortran ? " F " : " C ") + l.dtype + " sep " + l.separator;
    const VolumeReadResult r = read_volume(zip_of(image_store(l)));
    expect_truth(r, what);
    EXPECT_TRUE(r.spacing_from_file);
    // Dataset scale (0.05, 0.025, 0.2) x multiscale scale 10, in x, y, z whatever the axis order.
    EXPECT_TRUE(r.image.spacing.isApprox(Eigen::Vector3d(0.5, 0.25, 2.0), 1e-12)) << what << " " << r.image.spacing.transpose();
    EXPECT_EQ(r.image.unit, "um") << what;
  }
}

TEST(ZarrReader, ADirectoryStoreReadsAsItsZip) {
  Layout l;
  l.zlib = true;
  const Store s = image_store(l);
  const fs::path dir = directory_of(s, "dir");
  EXPECT_TRUE(is_zarr_directory(dir));
  EXPECT_TRUE(is_volume_file_name(dir));
  expect_truth(read_volume_file(dir), "directory");
  // The packed zip holds only what the read needs: not the root image's own arrays, nor level 1.
  const std::string packed = read_zarr_directory(dir);
  EXPECT_EQ(detect_volume_format(packed), VolumeFormat::OmeZarr);
  expect_truth(read_volume(packed), "packed");
  const io_detail::ZipZarrStore zs(packed);
  EXPECT_TRUE(zs.get("labels/cells/0/.zarray", 1 << 20));
  EXPECT_FALSE(zs.get("labels/cells/1/.zarray", 1 << 20));
  // The label image's folder itself is a store too (a path to labels/cells).
  expect_truth(read_volume_file(dir / "labels" / "cells"), "label image folder");
  // So is the labels group.
  expect_truth(read_volume_file(dir / "labels"), "labels group");
  fs::remove_all(dir);
}

TEST(ZarrReader, AZipWithTheStoreInOneFolderIsRead) {
  const Store s = image_store(Layout{});
  Store nested;
  for (const auto& [k, v] : s) nested["cells.zarr/" + k] = v;
  expect_truth(read_volume(zip_of(nested)), "folder in zip");
}

TEST(ZarrReader, PicksTheNamedLabelImageAndLevel) {
  Layout l;
  Store s = image_store(l, {"nuclei", "cells"});
  // "nuclei": listed first, one level, every voxel 7.
  s["labels/nuclei/.zattrs"] = s["labels/cells/.zattrs"];
  s["labels/nuclei/0/.zarray"] = json{{"zarr_format", 2}, {"shape", {kNz, kNy, kNx}}, {"chunks", {kNz, kNy, kNx}},
                                      {"dtype", "|u1"}, {"compressor", nullptr}, {"fill_value", 7}, {"order", "C"},
                                      {"filters", nullptr}}.dump();
  const std::string zip = zip_of(s);
  VolumeReadOptions o;
  o.zarr_labels = "cells";
  expect_truth(read_volume(zip, o), "cells by name");
  // Default: the first listed (nuclei), whose one chunk is missing: all fill_value.
  o.zarr_labels = "";
  EXPECT_EQ(read_volume(zip, o).image.labels, std::vector<std::uint32_t>(kNx * kNy * kNz, 7u));
  o.zarr_labels = "cells";
  o.zarr_level = 1;
  const VolumeReadResult r1 = read_volume(zip, o);
  EXPECT_TRUE(r1.image.spacing.isApprox(Eigen::Vector3d(1.0, 0.5, 4.0), 1e-12)) << r1.image.spacing.transpose();
  o.zarr_level = 2;
  EXPECT_EQ(error_code(zip, o), "invalid_parameter");
  o.zarr_level = 0;
  o.zarr_labels = "golgi";
  try {
    read_volume(zip, o);
    FAIL() << "no error";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "invalid_parameter");
    EXPECT_NE(std::string(e.what()).find("nuclei, cells"), std::string::npos) << e.what();
  }
}

TEST(ZarrReader, MissingChunksHoldTheFillValue) {
  Layout l;
  l.skip_background_chunks = true;
  Store s = image_store(l);
  expect_truth(read_volume(zip_of(s)), "fill 0");
  // Remove one chunk holding labels: with fill_value 0 its voxels become background; with 3 they become 3.
  s.erase("labels/cells/0/0.0.0");
  json za = json::parse(s["labels/cells/0/.zarray"]);
  const VolumeReadResult r0 = read_volume(zip_of(s));
  za["fill_value"] = 3;
  s["labels/cells/0/.zarray"] = za.dump();
  const VolumeReadResult r3 = read_volume(zip_of(s));
  for (std::int64_t z = 0; z < kNz; ++z)
    for (std::int64_t y = 0; y < kNy; ++y)
      for (std::int64_t x = 0; x < kNx; ++x) {
        const bool in_chunk = z < 2 && y < 2 && x < 2;
        EXPECT_EQ(r0.image.at(x, y, z), in_chunk ? 0u : truth(x, y, z));
        EXPECT_EQ(r3.image.at(x, y, z), in_chunk ? 3u : truth(x, y, z));
      }
  za["fill_value"] = -1;
  s["labels/cells/0/.zarray"] = za.dump();
  EXPECT_EQ(error_code(zip_of(s)), "invalid_label");
}

TEST(ZarrReader, RefusesWhatItCannotReadWithTheCheckThatFailed) {
  const Store good = image_store(Layout{});
  auto with = [&](const std::string& key, const std::function<void(json&)>& edit) {
    Store s = good;
    json j = json::parse(s[key]);
    edit(j);
    s[key] = j.dump();
    return zip_of(s);
  };
  const std::string za = "labels/cells/0/.zarray";
  EXPECT_EQ(error_code(with(za, [](json& j) { j["compressor"] = {{"id", "lz4"}}; })), "unsupported_format");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["filters"] = {{{"id", "delta"}, {"dtype", "<u2"}}}; })), "unsupported_format");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["zarr_format"] = 3; })), "unsupported_format");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["dtype"] = "<c8"; })), "unsupported_datatype");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["order"] = "K"; })), "parse_error");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["chunks"] = {2, 2}; })), "parse_error");
  EXPECT_EQ(error_code(with(za, [](json& j) { j["shape"] = {3, 4, -5}; })), "parse_error");
  // A channel axis of size 2 is not squeezed: two images, refused with the axes named.
  Layout two_channels;
  two_channels.axes = "czyx";
  Store s2 = image_store(two_channels);
  json z2 = json::parse(s2[za]);
  z2["shape"][0] = 2;
  s2[za] = z2.dump();
  try {
    read_volume(zip_of(s2));
    FAIL() << "no error";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "invalid_volume");
    EXPECT_NE(std::string(e.what()).find("axis 'c' has size 2"), std::string::npos) << e.what();
  }
  // A 2-D label image is not a volume.
  Layout flat;
  flat.axes = "yx";
  EXPECT_EQ(error_code(zip_of(image_store(flat))), "invalid_volume");
  // Dataset path escaping the store.
  EXPECT_EQ(error_code(with("labels/cells/.zattrs", [](json& j) { j["multiscales"][0]["datasets"][0]["path"] = "../../etc"; })),
            "parse_error");
  EXPECT_EQ(error_code(with("labels/cells/.zattrs", [](json& j) { j["multiscales"][0]["datasets"][0]["coordinateTransformations"][0]["scale"][1] = -1; })),
            "invalid_volume");
  // Corrupt chunk data: truncated zlib, a raw chunk of the wrong size, a negative label in a signed chunk.
  Layout zl;
  zl.zlib = true;
  Store s3 = image_store(zl);
  s3["labels/cells/0/0.0.0"].resize(s3["labels/cells/0/0.0.0"].size() / 2);
  EXPECT_EQ(error_code(zip_of(s3)), "parse_error");
  Store s4 = good;
  s4["labels/cells/0/0.0.0"] += "xx";
  EXPECT_EQ(error_code(zip_of(s4)), "parse_error");
  Layout signed_layout;
  signed_layout.dtype = "<i2";
  Store s5 = image_store(signed_layout);
  s5["labels/cells/0/0.1.1"].replace(0, 2, encode("<i2", -4));
  try {
    read_volume(zip_of(s5));
    FAIL() << "no error";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "invalid_label");
    EXPECT_NE(std::string(e.what()).find("labels/cells/0/0.1.1"), std::string::npos) << e.what();
  }
  // A zip without zarr metadata is not a volume; neither is JSON that is not.
  EXPECT_EQ(detect_volume_format(io_detail::write_zip({{"a.txt", "hello"}})), VolumeFormat::Unknown);
  Store s6 = good;
  s6["labels/cells/.zattrs"] = "{\"multiscales\": [";
  EXPECT_EQ(error_code(zip_of(s6)), "parse_error");
}

TEST(ZarrReader, LimitsAreCheckedBeforeAllocating) {
  // 100000^3 voxels announced by a store of a few hundred bytes: refused from the metadata.
  Store s = image_store(Layout{});
  json za = json::parse(s["labels/cells/0/.zarray"]);
  za["shape"] = {100000, 100000, 100000};
  s["labels/cells/0/.zarray"] = za.dump();
  EXPECT_EQ(error_code(zip_of(s)), "limit_exceeded");
  // A modest image in chunks larger than the voxel limit.
  VolumeReadOptions o;
  o.limits.max_voxels = 1000;
  za["shape"] = {3, 4, 5};
  za["chunks"] = {1, 1, 5000};
  s["labels/cells/0/.zarray"] = za.dump();
  EXPECT_EQ(error_code(zip_of(s), o), "limit_exceeded");
  // The chunk grid as a whole: many chunks, each far bigger than the image.
  za["shape"] = {30, 30, 1};
  za["chunks"] = {1, 1, 500};
  s["labels/cells/0/.zarray"] = za.dump();
  EXPECT_EQ(error_code(zip_of(s), o), "limit_exceeded");
  // The image itself over the limit.
  o.limits.max_voxels = 59;
  EXPECT_EQ(error_code(zip_of(image_store(Layout{})), o), "limit_exceeded");
  o.limits.max_voxels = 60;
  expect_truth(read_volume(zip_of(image_store(Layout{})), o), "at the limit");
}

TEST(ZarrReader, BooleanMask) {
  Store s;
  s[".zattrs"] = json{{"multiscales", {{{"version", "0.4"}, {"axes", axes_json("zyx", "nanometer")},
                                         {"datasets", {{{"path", "0"}}}}}}}}.dump();
  s["0/.zarray"] = json{{"zarr_format", 2}, {"shape", {1, 1, 3}}, {"chunks", {1, 1, 3}}, {"dtype", "|b1"},
                        {"compressor", nullptr}, {"fill_value", false}, {"order", "C"}, {"filters", nullptr}}.dump();
  s["0/0.0.0"] = std::string("\x01\x00\x01", 3);
  const VolumeReadResult r = read_volume(zip_of(s));
  EXPECT_EQ(r.image.labels, (std::vector<std::uint32_t>{1, 0, 1}));
  EXPECT_EQ(r.image.unit, "nm");
  EXPECT_FALSE(r.spacing_from_file);
  // Notes say what was assumed: a root image not marked as labels.
  EXPECT_FALSE(r.notes.empty());
}

}  // namespace
}  // namespace wish
