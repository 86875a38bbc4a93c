#include "core/pipeline/class_map.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/common/errors.hpp"

namespace wish {
namespace {

// Okabe & Ito's colour-blind-safe set (without black), then a second set for models with more classes.
constexpr std::array<std::array<std::uint8_t, 3>, 14> kClassColours{{{230, 159, 0},
                                                                     {86, 180, 233},
                                                                     {0, 158, 115},
                                                                     {240, 228, 66},
                                                                     {0, 114, 178},
                                                                     {213, 94, 0},
                                                                     {204, 121, 167},
                                                                     {153, 68, 85},
                                                                     {68, 170, 153},
                                                                     {136, 34, 85},
                                                                     {221, 204, 119},
                                                                     {51, 34, 136},
                                                                     {17, 119, 51},
                                                                     {170, 68, 153}}};
constexpr std::array<std::uint8_t, 3> kNovelColour{255, 255, 255};
constexpr std::array<std::uint8_t, 3> kRefusedColour{128, 128, 128};

double probability_of(const Prediction& p, const std::string& label) {
  for (const auto& [name, probability] : p.probabilities)
    if (name == label) return probability;
  return 0;
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

std::string class_map_name(const std::string& model_name) {
  std::string n = model_name.empty() ? std::string("wish") : model_name;
  for (char& c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  if (n.front() == '.') n.front() = '_';
  return n;
}

std::uint8_t ClassMapLegend::class_value(const std::string& label) const {
  const auto it = std::find(classes.begin(), classes.end(), label);
  if (it == classes.end())
    throw InvalidInputError("invalid_label", "class '" + label + "' is not one of the model's", {{"label", label}});
  return static_cast<std::uint8_t>(it - classes.begin() + 1);
}

std::vector<std::array<std::uint8_t, 3>> ClassMapLegend::palette() const {
  std::vector<std::array<std::uint8_t, 3>> p(entries.size() + 1, {0, 0, 0});
  for (const Entry& e : entries) p[e.value] = e.rgb;
  return p;
}

ClassMapLegend class_map_legend(const std::vector<std::string>& classes) {
  if (classes.size() > 253)
    throw InvalidInputError("invalid_parameter", "a class map holds at most 253 classes (8-bit values with novel and "
                                                 "refused); the model has " + std::to_string(classes.size()));
  ClassMapLegend legend;
  legend.classes = classes;
  for (std::size_t k = 0; k < classes.size(); ++k)
    legend.entries.push_back({static_cast<std::uint8_t>(k + 1), classes[k], kClassColours[k % kClassColours.size()]});
  legend.entries.push_back({legend.novel_value(), "novel", kNovelColour});
  legend.entries.push_back({legend.refused_value(), "refused", kRefusedColour});
  return legend;
}

const ClassMapObject& ClassMap::add(const VolumeObjectResult& object) {
  ClassMapObject o;
  o.id = object.object.id;
  if (object.ok() && object.result && object.result->prediction) {
    const Prediction& p = *object.result->prediction;
    o.label = p.label;
    o.probability = probability_of(p, p.label);
    o.margin = p.margin;
    if (p.novelty) o.novel = p.novelty->novel;
    o.value = o.novel.value_or(false) ? legend_.novel_value() : legend_.class_value(p.label);
  } else {
    o.value = legend_.refused_value();
    o.error_code = object.error ? object.error->code() : "not_classified";
  }
  const auto at = std::lower_bound(objects_.begin(), objects_.end(), o.id,
                                   [](const ClassMapObject& a, std::uint32_t id) { return a.id < id; });
  return *objects_.insert(at, std::move(o));
}

std::uint8_t ClassMap::value_of(std::uint32_t id) const {
  const auto at = std::lower_bound(objects_.begin(), objects_.end(), id,
                                   [](const ClassMapObject& a, std::uint32_t i) { return a.id < i; });
  return at != objects_.end() && at->id == id ? at->value : 0;
}

LabelRowSource class_map_source(const volume::LabelImage& image, const volume::ObjectSet& objects, const ClassMap& map) {
  return [&image, &objects, &map](std::int64_t first, std::int64_t count, std::int64_t stride, std::uint8_t* out) {
    std::uint32_t last_id = 0;
    std::uint8_t last_value = 0;  // runs of one id (and the background, id 0) skip the lookup
    for (std::int64_t k = 0; k < count; ++k) {
      const std::uint32_t id = objects.id_at(image, static_cast<std::size_t>(first + k * stride));
      if (id != last_id) {
        last_id = id;
        last_value = id == 0 ? 0 : map.value_of(id);
      }
      out[k] = last_value;
    }
  };
}

std::string ngff_image_label_json(const ClassMap& map) {
  using json = nlohmann::json;
  const ClassMapLegend& legend = map.legend();
  json colors = json::array(), properties = json::array();
  for (const auto& e : legend.entries) {
    colors.push_back({{"label-value", e.value}, {"rgba", {e.rgb[0], e.rgb[1], e.rgb[2], 255}}});
    json objects = json::array();
    for (const ClassMapObject& o : map.objects()) {
      if (o.value != e.value) continue;
      json entry = {{"label_id", o.id}};
      if (o.error_code.empty()) {
        entry["class"] = o.label;
        entry["probability"] = number_or_null(o.probability);
        entry["margin"] = number_or_null(o.margin);
        entry["novel"] = o.novel ? json(*o.novel) : json(nullptr);
      } else {
        entry["error"] = o.error_code;
      }
      objects.push_back(std::move(entry));
    }
    properties.push_back({{"label-value", e.value}, {"class", e.name}, {"object_count", objects.size()},
                          {"objects", std::move(objects)}});
  }
  return json{{"version", "0.4"}, {"colors", colors}, {"properties", properties}, {"source", {{"image", "../../"}}}}
      .dump();
}

namespace {

LabelImageShape shape_of(const VolumeReadResult& read) {
  return {read.image.dims, read.image.spacing, read.image.unit};
}

bool ends_with(const std::string& s, const char* suffix) {
  const std::string x = suffix;
  return s.size() >= x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0;
}

}  // namespace

void write_class_map(const std::filesystem::path& path, const std::string& name, const VolumeReadResult& read,
                     const volume::ObjectSet& objects, const ClassMap& map) {
  const LabelRowSource source = class_map_source(read.image, objects, map);
  const std::uint8_t max_value = map.legend().refused_value();
  switch (read.format) {
    case VolumeFormat::Nifti: {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      if (!out) throw IoError("write_failed", "cannot open " + path.string() + " for writing", {{"path", path.string()}});
      write_nifti_labels(out, shape_of(read), source, max_value, read.nifti, ends_with(path.string(), ".gz"));
      return;
    }
    case VolumeFormat::Tiff:
      write_tiff_labels(path, shape_of(read), source, map.legend().palette());
      return;
    case VolumeFormat::OmeZarr: {
      DirectoryZarrStoreWriter store(path);
      write_zarr_labels(store, name, shape_of(read), read.zarr, source, ngff_image_label_json(map));
      return;
    }
    default:
      throw InvalidInputError("invalid_parameter", "no class map format for this input");
  }
}

ClassMapBytes class_map_bytes(const std::string& name, const VolumeReadResult& read, const volume::ObjectSet& objects,
                              const ClassMap& map) {
  const LabelRowSource source = class_map_source(read.image, objects, map);
  switch (read.format) {
    case VolumeFormat::Nifti: {
      std::ostringstream out;
      write_nifti_labels(out, shape_of(read), source, map.legend().refused_value(), read.nifti, true);
      return {out.str(), "application/gzip", ".nii.gz"};
    }
    case VolumeFormat::Tiff:
      return {tiff_labels_bytes(shape_of(read), source, map.legend().palette()), "image/tiff", ".tif"};
    case VolumeFormat::OmeZarr: {
      ZipZarrStoreWriter store;
      write_zarr_labels(store, name, shape_of(read), read.zarr, source, ngff_image_label_json(map));
      return {store.zip(), "application/zip", ".ome.zarr.zip"};
    }
    default:
      throw InvalidInputError("invalid_parameter", "no class map format for this input");
  }
}

}  // namespace wish
