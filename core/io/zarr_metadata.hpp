#pragma once
// Internal to core/io: which zarr array an OME-Zarr read takes, and how its axes become x, y, z (NGFF 0.4 on zarr
// v2; earlier NGFF versions' string axes and implied t, c, z, y, x are taken too, with a note).
//
// The store root may be
//   * an image with a labels/ group: labels/.zattrs {"labels": [names]}; the label image is labels/<name>
//     (`zarr_labels`, default the first listed);
//   * a labels/ group itself ({"labels": [...]} in its .zattrs);
//   * a label image (or any image) with "multiscales" in its .zattrs;
//   * a bare zarr array (.zarray, no OME metadata): axes z, y, x assumed (zarr's C order of a 3-D stack), with a note.
// From multiscales[0]: datasets[`zarr_level`].path is the array; its voxel size is the product of the dataset's and
// the multiscale's own "scale" coordinate transformations, per axis; the unit is the space axes' (NGFF's names:
// "nanometer" -> "nm", "micrometer" -> "um", ...). Axes not of type space must have size 1 (squeezed); there must be
// exactly three space axes, named x, y and z.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/io/volume_io.hpp"
#include "core/io/volume_readers.hpp"
#include "core/io/zarr_codecs.hpp"
#include "core/io/zarr_store.hpp"

namespace wish::io_detail {

struct ZarrArrayPlan {
  std::string path;                           // the array's key prefix ("labels/cells/0/"; "" for a bare array)
  std::vector<std::string> metadata_keys;     // every metadata key read on the way (for packing a directory)
  std::vector<std::int64_t> shape, chunks;    // per zarr dimension
  std::array<int, 3> space_dim{-1, -1, -1};   // zarr dimension of x, y, z
  VoxelType type = VoxelType::UInt8;
  bool swap = false;                          // the dtype's byte order differs from this machine's
  bool fortran_order = false;                 // "order": "F"
  char separator = '.';                       // "dimension_separator"
  ZarrCompressor compressor = ZarrCompressor::None;
  bool has_fill = false;                      // fill_value not null
  double fill_value = 0;                      // for missing chunks
  std::int64_t chunk_voxels = 0;              // product of chunks
  std::int64_t chunk_count = 0;               // number of chunks in the grid
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
  bool spacing_from_file = false;
  std::string unit;
  std::string datatype;                       // "uint16 (<u2)"
  std::vector<std::string> notes;
  ZarrLayout layout;                          // what a label image written beside this one keeps

  // The key of the chunk with grid index `linear` (C order over the chunk grid), e.g. "labels/cells/0/0.1.2".
  std::string chunk_key(std::int64_t linear) const;
};

// Reads the metadata and checks every limit that does not need a chunk. Throws parse_error, invalid_volume,
// invalid_parameter, unsupported_format, unsupported_datatype or LimitExceededError, naming the key.
ZarrArrayPlan plan_zarr_read(const ZarrStore& store, const VolumeReadOptions& options);

// The label image the metadata chooses, read chunk by chunk (zarr_reader.cpp); spacing / unit overrides are the
// caller's (read_volume).
VolumeReadResult read_zarr(const ZarrStore& store, const VolumeReadOptions& options, bool probabilities = false);

// Largest metadata document read (.zattrs, .zgroup, .zarray): larger ones are refused, not parsed.
inline constexpr std::uint64_t kMaxZarrMetadataBytes = 1u << 20;
// Largest encoded chunk accepted, for a chunk of `raw` bytes: compressors add a small header at worst.
inline std::uint64_t max_encoded_chunk_bytes(std::uint64_t raw) { return raw + raw / 8 + 4096; }

}  // namespace wish::io_detail
