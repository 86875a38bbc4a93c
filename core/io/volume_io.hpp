#pragma once
// Reading label volumes: NIfTI-1 (.nii, and .nii.gz through zlib), TIFF stacks (multi-page, through libtiff) and
// OME-Zarr label images (NGFF 0.4 on zarr v2: a store directory, or its zip in zarr's ZipStore layout; core/io/zarr_*).
// As with meshes, readers work on bytes (uploads arrive as bytes), detect the format from the content, check every
// limit *before* allocating, and report the first problem as a typed error:
//   code "parse_error"          malformed header or data        details: format, field / byte_offset
//   code "unsupported_datatype" a voxel type that is not a label details: format, datatype
//   code "invalid_label"        negative, non-integer or non-finite value, or above 2^32 - 1  details: voxel, value
//   code "limit_exceeded"       (LimitExceededError)            details: limit, value, allowed
//   code "unsupported_format"   (category UnsupportedFormat)    neither NIfTI-1, TIFF nor an OME-Zarr zip; or a zarr
//                               compressor / filter / format version this reader does not decode
//   code "invalid_volume"       OME-Zarr axes that are not three space axes (+ size-1 others), a missing array
//   code "invalid_parameter"    OME-Zarr --label-image names no label image, --level no multiscale level
// Supported voxel types: uint8, int8, int16, uint16, int32, uint32, int64, uint64 (OME-Zarr), float32, float64 (floats
// hold integers: label images are sometimes stored as floats; or they are a probability map, values in [0, 1] not all
// integers, held as fixed point: LabelImage::probability_scale). NIfTI's scl_slope / scl_inter are ignored (a label
// is a name, not a measurement) and noted when they are not the identity.
// Spacing: NIfTI pixdim[1..3] with xyzt_units; TIFF X/YResolution with ResolutionUnit, ImageJ's ImageDescription
// (`unit=`, `spacing=` for z) or OME-XML's PhysicalSize{X,Y,Z}[Unit]. `spacing_override` / `unit_override` replace
// what the file says (UroCell's NIfTI headers say 1 mm; the true voxel is 16 x 16 x 15 nm).

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/volume/label_image.hpp"

namespace wish {

enum class VolumeFormat { Unknown, Nifti, Tiff, OmeZarr };
const char* to_string(VolumeFormat format);

struct VolumeReadLimits {
  std::uint64_t max_bytes = 1ull << 30;          // input size (compressed, as sent)
  std::int64_t max_voxels = 512ll * 512 * 512;    // nx * ny * nz
  std::int64_t max_pages = 65536;                 // TIFF directories
};

struct VolumeReadOptions {
  VolumeReadLimits limits;
  std::optional<Eigen::Vector3d> spacing_override;  // x, y, z voxel size; each > 0 and finite
  std::optional<std::string> unit_override;
  // OME-Zarr only: which label image of an image's labels/ group (empty: the first listed) and which multiscale level
  // (0: full resolution).
  std::string zarr_labels;
  int zarr_level = 0;
};

// An OME-Zarr input's array as read: what a label image written beside it (a class map) keeps, so that it lines up
// with the input in napari or neuroglancer (the same axes, shape, chunks and coordinate transformations).
struct ZarrLayout {
  struct Axis {
    std::string name, type, unit;  // as in the file ("micrometer"); type and unit may be empty
  };
  std::vector<Axis> axes;                  // one per zarr dimension, in the array's order
  std::vector<std::int64_t> shape, chunks;
  std::array<int, 3> space_dim{-1, -1, -1};  // the zarr dimension of x, y, z
  std::vector<double> scale;               // per zarr dimension: the level's scale times the multiscale's
  std::vector<double> translation;         // per zarr dimension; empty when the file has none
  std::string label_image;                 // key prefix of the label image read ("labels/cells/"; "" for the root)
};

// A NIfTI-1 input's geometry fields as read (host byte order), so that an image written beside it (a class map)
// keeps its voxel-to-world mapping exactly: pixdim, units, the qform (quaternion and offsets) and the sform rows.
struct NiftiGeometry {
  std::array<float, 8> pixdim{};
  std::uint8_t xyzt_units = 0;
  std::int16_t qform_code = 0, sform_code = 0;
  std::array<float, 3> quatern{}, qoffset{};
  std::array<float, 12> srow{};  // srow_x, srow_y, srow_z
};

struct VolumeReadResult {
  volume::LabelImage image;
  VolumeFormat format = VolumeFormat::Unknown;
  std::string datatype;             // voxel type in the file: "int16", "float64", ...
  bool spacing_from_file = false;   // false: the file gave no spacing (1, 1, 1 assumed) or it was overridden
  std::vector<std::string> notes;   // what was ignored or assumed, one sentence each
  std::optional<ZarrLayout> zarr;   // OME-Zarr inputs only
  std::optional<NiftiGeometry> nifti;  // NIfTI inputs only
};

// NIfTI-1 (magic "n+1" at byte 344, either byte order, gzip-wrapped or not), TIFF ("II*\0" / "MM\0*") or a zip
// holding zarr metadata (.zgroup / .zattrs / .zarray): an OME-Zarr store as zarr's ZipStore writes it.
VolumeFormat detect_volume_format(std::string_view bytes);
// True when the bytes start like a volume (gzip magic or one of the above): lets a caller route uploads.
bool looks_like_volume(std::string_view bytes);

VolumeReadResult read_volume(std::string_view bytes, const VolumeReadOptions& options = {});
// A file (read whole) or an OME-Zarr store directory (read_zarr_directory).
VolumeReadResult read_volume_file(const std::filesystem::path& path, const VolumeReadOptions& options = {});
// True for names ending .nii, .nii.gz, .tif, .tiff, .zarr.zip (case-insensitive), and for zarr store directories.
bool is_volume_file_name(const std::filesystem::path& path);

// True when `path` is a directory holding zarr metadata (.zgroup, .zattrs or .zarray): a zarr store on disk.
bool is_zarr_directory(const std::filesystem::path& path);
// The OME-Zarr store directory as the bytes of its ZipStore zip (entries stored, not recompressed), holding only what
// the read needs: the metadata on the way to the chosen label image and level, and that level's chunks. The CLI
// sends these bytes down the same path as an HTTP upload of the store's zip. Checks max_bytes while collecting.
std::string read_zarr_directory(const std::filesystem::path& path, const VolumeReadOptions& options = {});
// The bytes of a volume input named on a command line: a zarr store directory as above, else the file's content.
std::string read_volume_input(const std::filesystem::path& path, const VolumeReadOptions& options = {});

// Writes a NIfTI-1 single file (little endian, uint8 / int16 / uint16 / int32 / uint32 / float32 / float64 by
// `datatype` name; a probability map as float32 / float64 probabilities), gzip-compressed when `gzip`. For tests, round trips and exporting cleaned label images.
std::string write_nifti(const volume::LabelImage& image, std::string_view datatype = "uint32", bool gzip = false);

}  // namespace wish
