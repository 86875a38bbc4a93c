// OME-Zarr label images: the chosen array (core/io/zarr_metadata.hpp) read chunk by chunk into a LabelImage (x
// fastest). Each chunk is decoded whole (core/io/zarr_codecs.hpp) and copied row by row: a row is the run of voxels
// along the chunk's fastest dimension (the last in C order, the first in F order), clipped to the array's shape, so
// the padding zarr keeps in edge chunks is never read as labels. A chunk missing from the store holds fill_value.
#include <cmath>
#include <fstream>
#include <limits>

#include "core/common/errors.hpp"
#include "core/io/zarr_metadata.hpp"

namespace wish {
namespace io_detail {
namespace {

// fill_value as a label; refused like a voxel (invalid_label) when a missing chunk needs it and it is not one.
std::uint32_t fill_label(const ZarrArrayPlan& plan) {
  const double v = plan.fill_value;
  const char* why = !std::isfinite(v) ? "not finite" : v < 0 ? "negative" : v != std::floor(v) ? "not an integer"
                    : v > static_cast<double>(std::numeric_limits<std::uint32_t>::max()) ? "above 2^32 - 1" : nullptr;
  if (why)
    throw InvalidInputError("invalid_label", "OME-Zarr " + plan.path + ".zarray: fill_value " + std::to_string(v) +
                                                 " (the value of its missing chunks) is not a label (" + why + ")",
                            {{"format", std::string("ome-zarr")}, {"value", v}});
  return static_cast<std::uint32_t>(v);
}

}  // namespace

VolumeReadResult read_zarr(const ZarrStore& store, const VolumeReadOptions& options, bool probabilities) {
  const ZarrArrayPlan plan = plan_zarr_read(store, options);
  const std::size_t ndim = plan.shape.size();
  VolumeReadResult r;
  r.format = VolumeFormat::OmeZarr;
  r.datatype = plan.datatype;
  r.notes = plan.notes;
  r.image.dims = {plan.shape[plan.space_dim[0]], plan.shape[plan.space_dim[1]], plan.shape[plan.space_dim[2]]};
  r.image.spacing = plan.spacing;
  r.image.unit = plan.unit;
  r.spacing_from_file = plan.spacing_from_file;
  r.zarr = plan.layout;
  r.image.labels.assign(static_cast<std::size_t>(r.image.voxel_count()), 0);
  if (probabilities) r.image.probability_scale = volume::LabelImage::kProbabilityScale;

  // Strides: within a decoded chunk (in elements) and in the output image (0 for the squeezed axes).
  std::vector<std::int64_t> chunk_stride(ndim, 1), out_stride(ndim, 0), grid(ndim, 1);
  if (plan.fortran_order)
    for (std::size_t d = 1; d < ndim; ++d) chunk_stride[d] = chunk_stride[d - 1] * plan.chunks[d - 1];
  else
    for (std::size_t d = ndim - 1; d-- > 0;) chunk_stride[d] = chunk_stride[d + 1] * plan.chunks[d + 1];
  out_stride[static_cast<std::size_t>(plan.space_dim[0])] = 1;
  out_stride[static_cast<std::size_t>(plan.space_dim[1])] = r.image.dims[0];
  out_stride[static_cast<std::size_t>(plan.space_dim[2])] = r.image.dims[0] * r.image.dims[1];
  for (std::size_t d = 0; d < ndim; ++d) grid[d] = (plan.shape[d] + plan.chunks[d] - 1) / plan.chunks[d];
  const std::size_t inner = plan.fortran_order ? 0 : ndim - 1;

  const std::size_t item = static_cast<std::size_t>(byte_size(plan.type));
  const std::size_t chunk_bytes = static_cast<std::size_t>(plan.chunk_voxels) * item;
  std::string decoded;
  std::vector<std::uint32_t> run(static_cast<std::size_t>(plan.chunks[inner]));
  std::vector<std::int64_t> chunk_index(ndim, 0), origin(ndim), extent(ndim), i(ndim);
  bool noted_missing = false;
  std::uint32_t* out = r.image.labels.data();

  for (std::int64_t linear = 0; linear < plan.chunk_count; ++linear) {
    for (std::size_t d = 0; d < ndim; ++d) {
      origin[d] = chunk_index[d] * plan.chunks[d];
      extent[d] = std::min(plan.chunks[d], plan.shape[d] - origin[d]);
    }
    const std::string key = plan.chunk_key(linear);
    const auto encoded = store.get(key, max_encoded_chunk_bytes(chunk_bytes));
    std::uint32_t fill = 0;
    if (!encoded) {
      if (!plan.has_fill && !noted_missing) r.notes.push_back("chunks missing and fill_value null: read as background");
      noted_missing = true;
      fill = plan.has_fill ? fill_label(plan) : 0;
    } else {
      decode_zarr_chunk(plan.compressor, *encoded, chunk_bytes, key, decoded);
    }
    if (encoded || fill != 0) {
      const std::string where = "OME-Zarr chunk '" + key + "'";
      std::fill(i.begin(), i.end(), 0);
      while (true) {  // every row of the chunk inside the array
        std::int64_t src = 0, dst = 0;
        for (std::size_t d = 0; d < ndim; ++d) {
          src += i[d] * chunk_stride[d];
          dst += (origin[d] + i[d]) * out_stride[d];
        }
        const std::int64_t len = extent[inner];
        if (encoded)
          convert_labels(reinterpret_cast<const unsigned char*>(decoded.data()) + src * static_cast<std::int64_t>(item), len,
                         plan.type, plan.swap, run.data(), src, where.c_str(), r.image.probability_scale);
        else
          std::fill(run.begin(), run.begin() + len, fill);
        const std::int64_t step = out_stride[inner];
        for (std::int64_t k = 0; k < len; ++k) out[dst + k * step] = run[static_cast<std::size_t>(k)];
        // Next row: odometer over every dimension but the inner one.
        std::size_t d = 0;
        for (; d < ndim; ++d) {
          if (d == inner) continue;
          if (++i[d] < extent[d]) break;
          i[d] = 0;
        }
        if (d == ndim) break;
      }
    }
    for (std::size_t d = ndim; d-- > 0;) {  // next chunk, C order over the grid (as chunk_key counts)
      if (++chunk_index[d] < grid[d]) break;
      chunk_index[d] = 0;
    }
  }
  if (plan.swap) r.notes.push_back("big-endian OME-Zarr");
  return r;
}

VolumeReadResult read_zarr_zip(std::string_view bytes, const VolumeReadOptions& options, bool probabilities) {
  const ZipZarrStore store(bytes);
  return read_zarr(store, options, probabilities);
}

}  // namespace io_detail

bool is_zarr_directory(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) return false;
  for (const char* m : {".zgroup", ".zattrs", ".zarray"})
    if (std::filesystem::is_regular_file(path / m, ec)) return true;
  return false;
}

std::string read_zarr_directory(const std::filesystem::path& path, const VolumeReadOptions& options) {
  if (!is_zarr_directory(path))
    throw IoError("file_not_found", path.string() + " is not a zarr store (a directory with .zgroup, .zattrs or .zarray)",
                  {{"path", path.string()}});
  const io_detail::DirectoryZarrStore store(path);
  const io_detail::ZarrArrayPlan plan = io_detail::plan_zarr_read(store, options);
  std::vector<std::pair<std::string, std::string>> entries;
  std::uint64_t total = 0;
  auto add = [&](const std::string& key, std::uint64_t bound) {
    auto value = store.get(key, bound);
    if (!value) return;
    total += value->size();
    if (total > options.limits.max_bytes)
      throw LimitExceededError("the OME-Zarr store " + path.string() + " holds more than the limit of " +
                                   std::to_string(options.limits.max_bytes) + " bytes for the chosen label image",
                               {{"limit", std::string("max_bytes")}, {"value", static_cast<std::int64_t>(total)},
                                {"allowed", static_cast<std::int64_t>(options.limits.max_bytes)}});
    entries.emplace_back(key, std::move(*value));
  };
  for (const auto& key : plan.metadata_keys) add(key, io_detail::kMaxZarrMetadataBytes);
  const std::uint64_t chunk_bytes = static_cast<std::uint64_t>(plan.chunk_voxels) * io_detail::byte_size(plan.type);
  for (std::int64_t c = 0; c < plan.chunk_count; ++c) add(plan.chunk_key(c), io_detail::max_encoded_chunk_bytes(chunk_bytes));
  return io_detail::write_zip(entries);
}

std::string read_volume_input(const std::filesystem::path& path, const VolumeReadOptions& options) {
  if (is_zarr_directory(path)) return read_zarr_directory(path, options);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("file_not_found", "cannot open '" + path.string() + "'", {{"file", path.string()}});
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes;
}

}  // namespace wish
