#include "core/io/zarr_metadata.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/common/errors.hpp"

namespace wish::io_detail {
namespace {

using nlohmann::json;
constexpr const char* kZarrFormat = "ome-zarr";
constexpr std::size_t kMaxDimensions = 32;

[[noreturn]] void bad(const std::string& key, const std::string& what) {
  throw InvalidInputError("parse_error", "OME-Zarr " + key + ": " + what,
                          {{"format", std::string(kZarrFormat)}, {"key", key}});
}
[[noreturn]] void invalid(const std::string& key, const std::string& what) {
  throw InvalidInputError("invalid_volume", "OME-Zarr " + key + ": " + what,
                          {{"format", std::string(kZarrFormat)}, {"key", key}});
}
[[noreturn]] void unsupported(const std::string& key, const std::string& what) {
  throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format", "OME-Zarr " + key + ": " + what,
                  {{"format", std::string(kZarrFormat)}, {"key", key}});
}
[[noreturn]] void bad_parameter(const std::string& parameter, const std::string& what) {
  throw InvalidInputError("invalid_parameter", "OME-Zarr: " + what, {{"parameter", parameter}});
}

// The document under `key` parsed as JSON; nullopt when the store has no such key.
std::optional<json> get_json(const ZarrStore& store, const std::string& key, std::vector<std::string>& read_keys) {
  const auto text = store.get(key, kMaxZarrMetadataBytes);
  if (!text) return std::nullopt;
  read_keys.push_back(key);
  json doc = json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) bad(key, "is not valid JSON");
  if (!doc.is_object()) bad(key, "is not a JSON object");
  return doc;
}

// A label or dataset path from the metadata becomes part of a key (and, for a directory, of a file path): no empty,
// "." or ".." segment, no leading "/", no backslash.
std::string checked_path(const std::string& key, const json& value, const char* what) {
  if (!value.is_string()) bad(key, std::string(what) + " is not a string");
  const std::string p = value.get<std::string>();
  if (p.empty() || p.front() == '/' || p.back() == '/' || p.find('\\') != std::string::npos || p.size() > 1024)
    bad(key, std::string(what) + " '" + p + "' is not a relative path");
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = std::min(p.find('/', start), p.size());
    const std::string seg = p.substr(start, end - start);
    if (seg.empty() || seg == "." || seg == "..") bad(key, std::string(what) + " '" + p + "' is not a relative path");
    start = end + 1;
  }
  return p;
}

std::int64_t positive_int(const std::string& key, const json& v, const char* field, std::int64_t min) {
  if (!v.is_number_integer()) bad(key, std::string(field) + " holds a value that is not an integer");
  const std::int64_t n = v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
                             ? std::numeric_limits<std::int64_t>::max()
                             : v.get<std::int64_t>();
  if (n < min) bad(key, std::string(field) + " holds " + std::to_string(n) + " (at least " + std::to_string(min) + ")");
  return n;
}

// "micrometer" -> "um": the short units the rest of WISH writes; an unknown unit is kept as written.
std::string short_unit(const std::string& unit) {
  static const std::pair<const char*, const char*> known[] = {
      {"angstrom", "angstrom"}, {"nanometer", "nm"}, {"micrometer", "um"}, {"millimeter", "mm"},
      {"centimeter", "cm"},     {"meter", "m"},      {"picometer", "pm"},  {"kilometer", "km"}};
  for (const auto& [name, abbreviation] : known)
    if (unit == name) return abbreviation;
  return unit;
}

struct Dtype {
  VoxelType type;
  bool swap;
};

Dtype parse_dtype(const std::string& key, const json& v) {
  if (!v.is_string())
    throw InvalidInputError("unsupported_datatype", "OME-Zarr " + key + ": structured dtypes are not label types",
                            {{"format", std::string(kZarrFormat)}, {"datatype", v.dump()}});
  const std::string d = v.get<std::string>();
  auto refuse = [&]() -> Dtype {
    throw InvalidInputError("unsupported_datatype", "OME-Zarr " + key + ": dtype '" + d +
                                                        "' is not a label type (u1, u2, u4, u8, i1, i2, i4, i8, f4, f8, b1; "
                                                        "either byte order)",
                            {{"format", std::string(kZarrFormat)}, {"datatype", d}});
  };
  if (d.size() < 3 || std::string_view("<>|=").find(d[0]) == std::string_view::npos) refuse();
  const std::string body = d.substr(1);
  VoxelType t{};
  if (body == "u1" || body == "b1") t = VoxelType::UInt8;
  else if (body == "i1") t = VoxelType::Int8;
  else if (body == "u2") t = VoxelType::UInt16;
  else if (body == "i2") t = VoxelType::Int16;
  else if (body == "u4") t = VoxelType::UInt32;
  else if (body == "i4") t = VoxelType::Int32;
  else if (body == "u8") t = VoxelType::UInt64;
  else if (body == "i8") t = VoxelType::Int64;
  else if (body == "f4") t = VoxelType::Float32;
  else if (body == "f8") t = VoxelType::Float64;
  else refuse();
  const bool little = std::endian::native == std::endian::little;
  const bool swap = (d[0] == '>' && little) || (d[0] == '<' && !little);
  return {t, swap && byte_size(t) > 1};
}

// Per-dimension scale of a coordinateTransformations list (1 where it has none); `found` is set when it has one.
// `translation` gets the list's translation (0 where it has none), applied after the scale as the list orders them
// (kept for a label image written beside this one; the meshes start at the first voxel's centre).
std::vector<double> scale_of(const std::string& key, const json& list, std::size_t ndim, bool& found,
                             std::vector<std::string>& notes, std::vector<double>& translation) {
  std::vector<double> scale(ndim, 1.0);
  translation.assign(ndim, 0.0);
  if (list.is_null()) return scale;
  if (!list.is_array()) bad(key, "coordinateTransformations is not a list");
  for (const json& t : list) {
    if (!t.is_object() || !t.contains("type") || !t["type"].is_string()) bad(key, "a coordinate transformation has no type");
    const std::string type = t["type"].get<std::string>();
    if (type == "translation") {
      notes.push_back("translation ignored: the mesh starts at the first voxel's centre");
      const json& t_values = t.value("translation", json());
      if (t_values.is_array() && t_values.size() == ndim)
        for (std::size_t d = 0; d < ndim; ++d)
          if (t_values[d].is_number() && std::isfinite(t_values[d].get<double>())) translation[d] += t_values[d].get<double>();
      continue;
    }
    if (type == "identity") continue;
    if (type != "scale") {
      notes.push_back("coordinate transformation '" + type + "' ignored");
      continue;
    }
    if (!t.contains("scale")) {
      notes.push_back("scale given by path ignored: voxel size 1 assumed along those axes");
      continue;
    }
    const json& s = t["scale"];
    if (!s.is_array() || s.size() != ndim)
      invalid(key, "a scale transformation has " + std::to_string(s.is_array() ? s.size() : 0) + " values for " +
                       std::to_string(ndim) + " axes");
    for (std::size_t d = 0; d < ndim; ++d) {
      if (!s[d].is_number()) bad(key, "scale value " + std::to_string(d) + " is not a number");
      const double v = s[d].get<double>();
      if (!(std::isfinite(v) && v > 0)) invalid(key, "scale value " + std::to_string(d) + " is " + s[d].dump() + " (must be finite and positive)");
      scale[d] *= v;
      translation[d] *= v;
    }
    found = true;
  }
  return scale;
}

struct Axis {
  std::string name, type, unit;
};

std::vector<Axis> axes_of(const std::string& key, const json& ms, std::vector<std::string>& notes) {
  std::vector<Axis> axes;
  if (!ms.contains("axes")) {
    // NGFF 0.1 / 0.2: always t, c, z, y, x.
    notes.push_back("no axes in the multiscales metadata (NGFF before 0.3): t, c, z, y, x assumed");
    for (const char* n : {"t", "c", "z", "y", "x"}) axes.push_back({n, "", ""});
    return axes;
  }
  const json& a = ms["axes"];
  if (!a.is_array() || a.size() > kMaxDimensions) bad(key, "axes is not a list of at most 32 axes");
  for (const json& e : a) {
    Axis axis;
    if (e.is_string()) {  // NGFF 0.3
      axis.name = e.get<std::string>();
    } else if (e.is_object() && e.contains("name") && e["name"].is_string()) {
      axis.name = e["name"].get<std::string>();
      if (e.contains("type") && e["type"].is_string()) axis.type = e["type"].get<std::string>();
      if (e.contains("unit") && e["unit"].is_string()) axis.unit = e["unit"].get<std::string>();
    } else {
      bad(key, "an axis has no name");
    }
    std::transform(axis.name.begin(), axis.name.end(), axis.name.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    axes.push_back(axis);
  }
  return axes;
}

const json* multiscales_of(const std::optional<json>& attrs) {
  if (!attrs || !attrs->contains("multiscales")) return nullptr;
  const json& m = (*attrs)["multiscales"];
  return m.is_array() && !m.empty() ? &m[0] : nullptr;
}

// The name of the label image to read from a {"labels": [...]} document: the asked-for one, or the first.
std::string choose_label(const std::string& key, const json& attrs, const std::string& wanted) {
  const json& list = attrs["labels"];
  if (!list.is_array() || list.empty()) invalid(key, "the labels list is empty");
  std::vector<std::string> names;
  for (const json& n : list) names.push_back(checked_path(key, n, "label name"));
  if (wanted.empty()) return names.front();
  if (std::find(names.begin(), names.end(), wanted) != names.end()) return wanted;
  std::string all;
  for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
  bad_parameter("labels", "no label image named '" + wanted + "' (the store has: " + all + ")");
}

}  // namespace

std::string ZarrArrayPlan::chunk_key(std::int64_t linear) const {
  const std::size_t n = shape.size();
  std::vector<std::int64_t> index(n, 0);
  for (std::size_t k = n; k-- > 0;) {
    const std::int64_t g = (shape[k] + chunks[k] - 1) / chunks[k];
    index[k] = linear % g;
    linear /= g;
  }
  std::string key = path;
  for (std::size_t k = 0; k < n; ++k) {
    if (k) key += separator;
    key += std::to_string(index[k]);
  }
  if (n == 0) key += "0";
  return key;
}

ZarrArrayPlan plan_zarr_read(const ZarrStore& store, const VolumeReadOptions& options) {
  ZarrArrayPlan plan;
  if (store.get("zarr.json", kMaxZarrMetadataBytes))
    unsupported("zarr.json", "zarr v3 stores (NGFF 0.5) are not read: save the label image as zarr v2 (NGFF 0.4)");

  // 1. Where the label image is: labels/<name>, <name> of a labels group, or the root.
  std::string prefix;
  std::optional<json> attrs = get_json(store, ".zattrs", plan.metadata_keys);
  if (store.get(".zgroup", kMaxZarrMetadataBytes)) plan.metadata_keys.push_back(".zgroup");
  if (attrs && attrs->contains("labels") && !attrs->contains("multiscales")) {
    prefix = choose_label(".zattrs", *attrs, options.zarr_labels) + "/";
  } else if (auto labels = get_json(store, "labels/.zattrs", plan.metadata_keys); labels && labels->contains("labels")) {
    prefix = "labels/" + choose_label("labels/.zattrs", *labels, options.zarr_labels) + "/";
    if (store.get("labels/.zgroup", kMaxZarrMetadataBytes)) plan.metadata_keys.push_back("labels/.zgroup");
  } else if (!options.zarr_labels.empty()) {
    bad_parameter("labels", "a label image named '" + options.zarr_labels + "' was asked for, but the store has no labels/ group");
  }
  if (!prefix.empty()) {
    attrs = get_json(store, prefix + ".zattrs", plan.metadata_keys);
    if (store.get(prefix + ".zgroup", kMaxZarrMetadataBytes)) plan.metadata_keys.push_back(prefix + ".zgroup");
  }

  // 2. The array: a multiscale level, or a bare array.
  std::vector<Axis> axes;
  std::vector<double> scale;
  const std::string attrs_key = prefix + ".zattrs";
  if (const json* ms = multiscales_of(attrs)) {
    if (!ms->is_object() || !ms->contains("datasets") || !(*ms)["datasets"].is_array() || (*ms)["datasets"].empty())
      bad(attrs_key, "multiscales[0] has no datasets");
    const json& datasets = (*ms)["datasets"];
    if (options.zarr_level < 0 || static_cast<std::size_t>(options.zarr_level) >= datasets.size())
      bad_parameter("level", "level " + std::to_string(options.zarr_level) + " does not exist: the label image has " +
                                 std::to_string(datasets.size()) + " level(s), 0 to " + std::to_string(datasets.size() - 1));
    const json& ds = datasets[static_cast<std::size_t>(options.zarr_level)];
    if (!ds.is_object() || !ds.contains("path")) bad(attrs_key, "dataset " + std::to_string(options.zarr_level) + " has no path");
    plan.path = prefix + checked_path(attrs_key, ds["path"], "dataset path") + "/";
    if (ms->contains("version") && (*ms)["version"].is_string() && (*ms)["version"].get<std::string>() != "0.4")
      plan.notes.push_back("NGFF version " + (*ms)["version"].get<std::string>() + " read as 0.4");
    axes = axes_of(attrs_key, *ms, plan.notes);
    bool found = false;
    std::vector<double> shift, global_shift;
    scale = scale_of(attrs_key, ds.contains("coordinateTransformations") ? ds["coordinateTransformations"] : json(), axes.size(),
                     found, plan.notes, shift);
    const std::vector<double> global = scale_of(attrs_key, ms->contains("coordinateTransformations") ? (*ms)["coordinateTransformations"] : json(),
                                                axes.size(), found, plan.notes, global_shift);
    for (std::size_t d = 0; d < axes.size(); ++d) {
      scale[d] *= global[d];
      shift[d] = shift[d] * global[d] + global_shift[d];
    }
    if (std::any_of(shift.begin(), shift.end(), [](double t) { return t != 0; })) plan.layout.translation = shift;
    plan.spacing_from_file = found;
    if (!prefix.empty() && attrs && !attrs->contains("image-label"))
      plan.notes.push_back("the label image has no image-label metadata");
    if (prefix.empty() && attrs && !attrs->contains("image-label"))
      plan.notes.push_back("the store has no labels/ group and its image is not marked image-label: read as a label image");
  } else if (store.get(prefix + ".zarray", kMaxZarrMetadataBytes)) {
    plan.path = prefix;
    plan.notes.push_back("a bare zarr array (no OME multiscales metadata): the last three axes taken as z, y, x, voxel size 1");
  } else {
    invalid(attrs_key, "neither OME multiscales metadata nor a zarr array here");
  }

  // 3. The array's own metadata.
  const std::string zkey = plan.path + ".zarray";
  const std::optional<json> za = get_json(store, zkey, plan.metadata_keys);
  if (!za) invalid(zkey, "the array's metadata is missing");
  if (!za->contains("zarr_format") || (*za)["zarr_format"] != 2) unsupported(zkey, "zarr_format is not 2");
  const json& shape = (*za).value("shape", json());
  const json& chunks = (*za).value("chunks", json());
  if (!shape.is_array() || !chunks.is_array() || shape.size() != chunks.size() || shape.size() > kMaxDimensions)
    bad(zkey, "shape and chunks must be lists of the same length (at most 32)");
  const std::size_t ndim = shape.size();
  for (std::size_t d = 0; d < ndim; ++d) {
    plan.shape.push_back(positive_int(zkey, shape[d], "shape", 0));
    plan.chunks.push_back(positive_int(zkey, chunks[d], "chunks", 1));
  }
  if (axes.empty()) {  // a bare array: z, y, x last, anything before must have size 1
    if (ndim < 3) invalid(zkey, "a label volume needs three dimensions; this array has " + std::to_string(ndim));
    for (std::size_t d = 0; d < ndim; ++d) axes.push_back({d + 3 == ndim ? "z" : d + 2 == ndim ? "y" : d + 1 == ndim ? "x" : "?", "", ""});
    scale.assign(ndim, 1.0);
  }
  if (axes.size() != ndim)
    invalid(zkey, "the array has " + std::to_string(ndim) + " dimensions but the multiscales metadata names " +
                      std::to_string(axes.size()) + " axes");

  // 4. Axes: x, y, z found by name; every other axis squeezed (size 1) or refused.
  std::string axis_list;
  for (const auto& a : axes) axis_list += (axis_list.empty() ? "" : ", ") + a.name + "=" + std::to_string(plan.shape[&a - axes.data()]);
  for (std::size_t d = 0; d < ndim; ++d) {
    const Axis& a = axes[d];
    const int role = a.name == "x" ? 0 : a.name == "y" ? 1 : a.name == "z" ? 2 : -1;
    if (role >= 0) {
      if (plan.space_dim[role] >= 0) invalid(zkey, "axis " + a.name + " appears twice (axes " + axis_list + ")");
      plan.space_dim[role] = static_cast<int>(d);
      continue;
    }
    if (a.type == "space") invalid(zkey, "space axis '" + a.name + "' is not x, y or z (axes " + axis_list + ")");
    if (plan.shape[d] != 1)
      invalid(zkey, "axis '" + a.name + "' has size " + std::to_string(plan.shape[d]) +
                        ": a label volume is one 3-D image (only t or c axes of size 1 are dropped; axes " + axis_list +
                        "); save one time point / channel per store");
  }
  for (int k = 0; k < 3; ++k)
    if (plan.space_dim[k] < 0)
      invalid(zkey, std::string("no ") + "xyz"[k] + " axis: a label volume needs x, y and z (axes " + axis_list + ")");

  for (std::size_t d = 0; d < ndim; ++d) plan.layout.axes.push_back({axes[d].name, axes[d].type, axes[d].unit});
  plan.layout.shape = plan.shape;
  plan.layout.chunks = plan.chunks;
  plan.layout.space_dim = plan.space_dim;
  plan.layout.scale = scale;
  plan.layout.label_image = prefix;

  // 5. Voxel size and unit.
  std::string unit;
  for (int k = 0; k < 3; ++k) {
    const int d = plan.space_dim[k];
    plan.spacing(k) = scale[static_cast<std::size_t>(d)];
    const std::string u = short_unit(axes[static_cast<std::size_t>(d)].unit);
    if (k == 0) unit = u;
    else if (u != unit) plan.notes.push_back("the axes have different units (" + unit + ", " + u + "): the x axis' unit kept");
  }
  plan.unit = unit;

  // 6. Encoding.
  const Dtype dt = parse_dtype(zkey, (*za).value("dtype", json()));
  plan.type = dt.type;
  plan.swap = dt.swap;
  plan.datatype = std::string(to_string(dt.type)) + " (" + (*za)["dtype"].get<std::string>() + ")";
  const json order = (*za).value("order", json("C"));
  if (order != "C" && order != "F") bad(zkey, "order must be \"C\" or \"F\"");
  plan.fortran_order = order == "F";
  const json sep = (*za).value("dimension_separator", json("."));
  if (sep != "." && sep != "/") bad(zkey, "dimension_separator must be \".\" or \"/\"");
  plan.separator = sep.get<std::string>()[0];
  const json filters = (*za).value("filters", json());
  if (!filters.is_null() && !(filters.is_array() && filters.empty()))
    unsupported(zkey, "filters (" + filters.dump().substr(0, 200) + ") are not decoded: store the labels without filters");
  const json compressor = (*za).value("compressor", json());
  if (!compressor.is_null()) {
    const std::string id = compressor.is_object() && compressor.contains("id") && compressor["id"].is_string()
                               ? compressor["id"].get<std::string>() : "";
    if (!zarr_compressor_from_id(id, plan.compressor))
      unsupported(zkey, "compressor '" + id + "' is not decoded (" + zarr_compressor_list() + ")");
  }
  const json fill = (*za).value("fill_value", json());
  plan.has_fill = !fill.is_null();
  if (fill.is_number()) plan.fill_value = fill.get<double>();
  else if (fill.is_boolean()) plan.fill_value = fill.get<bool>() ? 1 : 0;
  else if (fill == "NaN") plan.fill_value = std::numeric_limits<double>::quiet_NaN();
  else if (fill == "Infinity") plan.fill_value = std::numeric_limits<double>::infinity();
  else if (fill == "-Infinity") plan.fill_value = -std::numeric_limits<double>::infinity();
  else if (plan.has_fill) bad(zkey, "fill_value " + fill.dump().substr(0, 100) + " is not a number");

  // 7. Limits, before anything is allocated: the volume, one chunk, and the chunk grid as a whole (many chunks each
  // far larger than the volume would be decoded for nothing).
  const std::int64_t n = checked_voxel_count(plan.shape[plan.space_dim[0]], plan.shape[plan.space_dim[1]],
                                             plan.shape[plan.space_dim[2]], options.limits, kZarrFormat);
  const std::int64_t allowed = options.limits.max_voxels;
  auto over = [&](const std::string& what, double value, std::int64_t limit) {
    throw LimitExceededError("OME-Zarr " + zkey + ": " + what + " exceeds the limit of " + std::to_string(limit) + " voxels",
                             {{"limit", std::string("max_voxels")}, {"value", value}, {"allowed", limit}});
  };
  double chunk_voxels = 1, grid = 1;
  for (std::size_t d = 0; d < ndim; ++d) {
    chunk_voxels *= static_cast<double>(plan.chunks[d]);
    grid *= static_cast<double>((plan.shape[d] + plan.chunks[d] - 1) / plan.chunks[d]);
  }
  if (chunk_voxels > static_cast<double>(allowed)) over("a chunk of " + std::to_string(static_cast<std::int64_t>(chunk_voxels)) + " voxels", chunk_voxels, allowed);
  const std::int64_t grid_allowed = std::max<std::int64_t>(allowed, 4 * n);
  if (grid * chunk_voxels > static_cast<double>(grid_allowed))
    over("the chunk grid (" + std::to_string(static_cast<std::int64_t>(grid)) + " chunks of " +
             std::to_string(static_cast<std::int64_t>(chunk_voxels)) + " voxels)", grid * chunk_voxels, grid_allowed);
  plan.chunk_voxels = static_cast<std::int64_t>(chunk_voxels);
  plan.chunk_count = static_cast<std::int64_t>(grid);
  return plan;
}

}  // namespace wish::io_detail
