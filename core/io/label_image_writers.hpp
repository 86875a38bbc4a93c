#pragma once
// Writing an 8-bit label image of a volume that was read (a class map: core/pipeline/class_map.hpp) in the input's
// own format, keeping its geometry, so it opens beside the input in napari, Fiji or neuroglancer:
//   NIfTI-1  the input's pixdim, units, qform and sform copied (NiftiGeometry); uint8, intent NIFTI_INTENT_LABEL
//            (1002), cal_min 0 / cal_max the largest value; gzip when asked (.nii.gz)
//   TIFF     one 8-bit page per z slice with a palette (the legend's colours: Fiji shows the classes coloured),
//            ImageJ metadata (unit, spacing of z, slices) and X/YResolution (1 / voxel size); deflate
//   OME-Zarr a labels/<name> image-label group (NGFF 0.4 on zarr v2) written into a store: the input's axes, shape,
//            chunks and coordinate transformations (ZarrLayout), zlib chunks, dimension_separator "/", the
//            `image-label` metadata the caller gives (colours, properties, source), and the name added to
//            labels/.zattrs's list beside the labels already there
// Streaming: the values come from a row source, asked for one z slice (NIfTI, TIFF) or one chunk row (OME-Zarr) at
// a time, so no writer holds a second copy of the volume: at most one slice or one chunk, and its encoding.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/io/volume_io.hpp"

namespace wish {

// Fills out[0 .. count) with the values of voxels first, first + stride, ... (voxel index x + nx (y + ny z)).
using LabelRowSource =
    std::function<void(std::int64_t first, std::int64_t count, std::int64_t stride, std::uint8_t* out)>;

struct LabelImageShape {
  std::array<std::int64_t, 3> dims{0, 0, 0};
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
  std::string unit;
};

// NIfTI-1: the geometry of `like` (a NIfTI input; absent: pixdim and units from `shape` only).
void write_nifti_labels(std::ostream& out, const LabelImageShape& shape, const LabelRowSource& source,
                        std::uint8_t max_value, const std::optional<NiftiGeometry>& like, bool gzip);

// TIFF: `palette` gives the RGB colour of each value (missing values black).
void write_tiff_labels(const std::filesystem::path& path, const LabelImageShape& shape, const LabelRowSource& source,
                       const std::vector<std::array<std::uint8_t, 3>>& palette);
std::string tiff_labels_bytes(const LabelImageShape& shape, const LabelRowSource& source,
                              const std::vector<std::array<std::uint8_t, 3>>& palette);

// A zarr v2 store being written: a directory on disk, or entries gathered for a zip (an HTTP answer).
class ZarrStoreWriter {
 public:
  virtual ~ZarrStoreWriter() = default;
  virtual void put(const std::string& key, std::string value) = 0;
  virtual std::optional<std::string> existing(const std::string& key) const = 0;  // for merging labels/.zattrs
};

class DirectoryZarrStoreWriter final : public ZarrStoreWriter {
 public:
  explicit DirectoryZarrStoreWriter(std::filesystem::path root) : root_(std::move(root)) {}
  void put(const std::string& key, std::string value) override;
  std::optional<std::string> existing(const std::string& key) const override;

 private:
  std::filesystem::path root_;
};

class ZipZarrStoreWriter final : public ZarrStoreWriter {
 public:
  void put(const std::string& key, std::string value) override;
  std::optional<std::string> existing(const std::string& key) const override;
  std::string zip() const;  // zarr's ZipStore layout (entries stored), as the readers take it

 private:
  std::vector<std::pair<std::string, std::string>> entries_;
};

// OME-Zarr: labels/<name> with `layout`'s axes (or z, y, x from `shape` when absent). `image_label_json` is the
// NGFF "image-label" object (version, colors, properties, source) as JSON text. Throws
// InvalidInputError("invalid_parameter") for a name that is not one path segment.
void write_zarr_labels(ZarrStoreWriter& store, const std::string& name, const LabelImageShape& shape,
                       const std::optional<ZarrLayout>& layout, const LabelRowSource& source,
                       const std::string& image_label_json);

}  // namespace wish
