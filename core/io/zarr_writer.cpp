// OME-Zarr label images (core/io/label_image_writers.hpp): labels/<name> as an NGFF 0.4 image-label multiscale with
// one level ("0"), the input's axes, shape, chunks and coordinate transformations, uint8 zlib chunks. Chunks are made
// one at a time in C order over the chunk grid, each filled row by row along its last (fastest) dimension from the
// row source, compressed and handed to the store: one chunk in memory at a time.
#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include <zlib.h>

#include "core/common/errors.hpp"
#include "core/io/label_image_writers.hpp"
#include "core/io/zarr_store.hpp"

namespace wish {
namespace {

using json = nlohmann::json;

std::string zlib_bytes(const std::vector<std::uint8_t>& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string out(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, raw.data(), static_cast<uLong>(raw.size()), 5) != Z_OK)
    throw WishError(ErrorCategory::Internal, "zlib_error", "zlib could not compress an OME-Zarr chunk");
  out.resize(size);
  return out;
}

// NGFF unit names of the short units the readers produce ("um" -> "micrometer"); other units kept as they are.
std::string ngff_unit(const std::string& unit) {
  static const std::pair<const char*, const char*> names[] = {{"nm", "nanometer"}, {"um", "micrometer"},
                                                              {"mm", "millimeter"}, {"cm", "centimeter"},
                                                              {"m", "meter"},       {"pm", "picometer"}};
  for (const auto& [short_name, name] : names)
    if (unit == short_name) return name;
  return unit;
}

// z, y, x from the image's shape when the input was not an OME-Zarr store.
ZarrLayout default_layout(const LabelImageShape& shape) {
  ZarrLayout l;
  for (int k = 2; k >= 0; --k) {
    l.axes.push_back({std::string(1, "xyz"[k]), "space", ngff_unit(shape.unit)});
    l.shape.push_back(shape.dims[static_cast<std::size_t>(k)]);
    l.chunks.push_back(std::min<std::int64_t>(64, shape.dims[static_cast<std::size_t>(k)]));
    l.scale.push_back(shape.spacing(k));
  }
  l.space_dim = {2, 1, 0};
  return l;
}

json axis_json(const ZarrLayout::Axis& a) {
  json out = {{"name", a.name}};
  if (!a.type.empty()) out["type"] = a.type;
  if (!a.unit.empty()) out["unit"] = a.unit;
  return out;
}

void check_name(const std::string& name) {
  const bool plain = !name.empty() && name.size() <= 255 && name != "." && name != ".." &&
                     name.find_first_of("/\\") == std::string::npos && name.front() != '.';
  if (!plain)
    throw InvalidInputError("invalid_parameter", "'" + name + "' cannot name a label image (labels/NAME: one path segment)",
                            {{"parameter", std::string("name")}});
}

}  // namespace

void DirectoryZarrStoreWriter::put(const std::string& key, std::string value) {
  const std::filesystem::path path = root_ / key;
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(value.data(), static_cast<std::streamsize>(value.size()));
  if (!out) throw IoError("write_failed", "cannot write " + path.string(), {{"path", path.string()}});
}

std::optional<std::string> DirectoryZarrStoreWriter::existing(const std::string& key) const {
  std::ifstream in(root_ / key, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void ZipZarrStoreWriter::put(const std::string& key, std::string value) {
  for (auto& [k, v] : entries_)
    if (k == key) {
      v = std::move(value);
      return;
    }
  entries_.emplace_back(key, std::move(value));
}

std::optional<std::string> ZipZarrStoreWriter::existing(const std::string& key) const {
  for (const auto& [k, v] : entries_)
    if (k == key) return v;
  return std::nullopt;
}

std::string ZipZarrStoreWriter::zip() const { return io_detail::write_zip(entries_); }

void write_zarr_labels(ZarrStoreWriter& store, const std::string& name, const LabelImageShape& shape,
                       const std::optional<ZarrLayout>& input_layout, const LabelRowSource& source,
                       const std::string& image_label_json) {
  const json image_label = json::parse(image_label_json);
  check_name(name);
  const ZarrLayout layout = input_layout ? *input_layout : default_layout(shape);
  const std::size_t ndim = layout.shape.size();
  const std::string group = "labels/" + name + "/";

  // The labels group lists its label images: this one is added beside those already there.
  json labels = {{"labels", json::array()}};
  if (auto text = store.existing("labels/.zattrs")) {
    const json old = json::parse(*text, nullptr, false);
    if (old.is_object()) labels = old;
    if (!labels.contains("labels") || !labels["labels"].is_array()) labels["labels"] = json::array();
  }
  if (std::find(labels["labels"].begin(), labels["labels"].end(), name) == labels["labels"].end())
    labels["labels"].push_back(name);
  if (!store.existing(".zgroup")) store.put(".zgroup", json{{"zarr_format", 2}}.dump());
  store.put("labels/.zgroup", json{{"zarr_format", 2}}.dump());
  store.put("labels/.zattrs", labels.dump(2));

  json axes = json::array();
  for (const auto& a : layout.axes) axes.push_back(axis_json(a));
  json transforms = json::array({{{"type", "scale"}, {"scale", layout.scale}}});
  if (!layout.translation.empty()) transforms.push_back({{"type", "translation"}, {"translation", layout.translation}});
  const json attrs = {
      {"multiscales", json::array({{{"version", "0.4"},
                                    {"name", name},
                                    {"axes", axes},
                                    {"datasets", json::array({{{"path", "0"}, {"coordinateTransformations", transforms}}})}}})},
      {"image-label", image_label}};
  store.put(group + ".zgroup", json{{"zarr_format", 2}}.dump());
  store.put(group + ".zattrs", attrs.dump(2));
  store.put(group + "0/.zarray", json{{"zarr_format", 2},
                                      {"shape", layout.shape},
                                      {"chunks", layout.chunks},
                                      {"dtype", "|u1"},
                                      {"compressor", {{"id", "zlib"}, {"level", 5}}},
                                      {"fill_value", 0},
                                      {"order", "C"},
                                      {"filters", nullptr},
                                      {"dimension_separator", "/"}}
                                     .dump(2));

  // Strides of the zarr dimensions in the image (x fastest; 0 for the dimensions of size 1 that are not space).
  std::vector<std::int64_t> stride(ndim, 0), grid(ndim), index(ndim, 0);
  const std::int64_t image_stride[3] = {1, shape.dims[0], shape.dims[0] * shape.dims[1]};
  for (int k = 0; k < 3; ++k) stride[static_cast<std::size_t>(layout.space_dim[static_cast<std::size_t>(k)])] = image_stride[k];
  std::int64_t chunk_voxels = 1, chunk_count = 1;
  for (std::size_t d = 0; d < ndim; ++d) {
    grid[d] = (layout.shape[d] + layout.chunks[d] - 1) / layout.chunks[d];
    chunk_voxels *= layout.chunks[d];
    chunk_count *= grid[d];
  }
  const std::size_t inner = ndim - 1;  // C order: the last dimension is the fastest
  std::vector<std::uint8_t> chunk(static_cast<std::size_t>(chunk_voxels));
  std::vector<std::int64_t> chunk_stride(ndim, 1), origin(ndim), extent(ndim), i(ndim);
  for (std::size_t d = ndim - 1; d-- > 0;) chunk_stride[d] = chunk_stride[d + 1] * layout.chunks[d + 1];
  for (std::int64_t c = 0; c < chunk_count; ++c) {
    std::fill(chunk.begin(), chunk.end(), 0);  // zarr keeps edge chunks whole: the padding is the fill value
    for (std::size_t d = 0; d < ndim; ++d) {
      origin[d] = index[d] * layout.chunks[d];
      extent[d] = std::min(layout.chunks[d], layout.shape[d] - origin[d]);
    }
    std::fill(i.begin(), i.end(), 0);
    while (true) {  // every row of the chunk inside the array
      std::int64_t first = 0, at = 0;
      for (std::size_t d = 0; d < ndim; ++d) {
        first += (origin[d] + i[d]) * stride[d];
        at += i[d] * chunk_stride[d];
      }
      source(first, extent[inner], stride[inner], chunk.data() + at);
      std::size_t d = 0;
      for (; d < inner; ++d) {
        const std::size_t k = inner - 1 - d;  // odometer over the outer dimensions, last outer fastest
        if (++i[k] < extent[k]) break;
        i[k] = 0;
      }
      if (d == inner) break;
    }
    std::string key = group + "0/";
    for (std::size_t d = 0; d < ndim; ++d) key += (d ? "/" : "") + std::to_string(index[d]);
    store.put(key, zlib_bytes(chunk));
    for (std::size_t d = ndim; d-- > 0;) {  // next chunk, C order over the grid
      if (++index[d] < grid[d]) break;
      index[d] = 0;
    }
  }
}

}  // namespace wish
