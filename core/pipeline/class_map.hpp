#pragma once
// The class map of a label volume (issue 39): an 8-bit label image of the input's geometry in which every object's
// voxels carry what it was classified as, written in the input's own format (core/io/label_image_writers.hpp), so a
// lab sees which object is which beside the raw data in napari, Fiji or neuroglancer.
// Values (the legend, fixed per model):
//   0        background, and every object a filter dropped (specks, unselected, truncated with drop_truncated)
//   1..K     the predicted class, in the model's class order
//   K + 1    novel: unlike every class the model knows (its novelty flag)
//   K + 2    refused: the object could not be described (its error is in the JSON and the table)
// Colours are fixed per value: the classes take a colour-blind-safe palette (Okabe & Ito 2008) in order, then a
// second set; novel is white and refused mid grey. A fragment merged into an object carries the object's value.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/io/label_image_writers.hpp"
#include "core/pipeline/volume_description.hpp"

namespace wish {

struct ClassMapLegend {
  struct Entry {
    std::uint8_t value = 0;
    std::string name;  // the class, "novel" or "refused"
    std::array<std::uint8_t, 3> rgb{};
  };
  std::vector<std::string> classes;  // the model's, in order
  std::vector<Entry> entries;        // values 1 .. K + 2
  std::uint8_t novel_value() const { return static_cast<std::uint8_t>(classes.size() + 1); }
  std::uint8_t refused_value() const { return static_cast<std::uint8_t>(classes.size() + 2); }
  // 1-based value of a class; throws InvalidInputError("invalid_label") for a class the model does not have.
  std::uint8_t class_value(const std::string& label) const;
  std::vector<std::array<std::uint8_t, 3>> palette() const;  // RGB by value, 0 black
};

// The label image name of a model's class map (OME-Zarr labels/<name>, file names): the model's name with every
// character but letters, digits, '-', '_' and '.' made '_' ("wish" for an unnamed model; never a leading '.').
std::string class_map_name(const std::string& model_name);

// Throws InvalidInputError("invalid_parameter") for more than 253 classes (values must fit 8 bits).
ClassMapLegend class_map_legend(const std::vector<std::string>& classes);

// One object as the class map shows it (and its NGFF per-object properties).
struct ClassMapObject {
  std::uint32_t id = 0;
  std::uint8_t value = 0;
  std::string label;              // predicted class; empty when refused
  double probability = 0;         // of the predicted class
  double margin = 0;
  std::optional<bool> novel;      // none: the model has no novelty calibration
  std::string error_code;         // refused: the object's error code
};

class ClassMap {
 public:
  explicit ClassMap(ClassMapLegend legend) : legend_(std::move(legend)) {}
  const ClassMapLegend& legend() const { return legend_; }
  // The object's value from its result (its prediction, or its error); objects arrive in id order.
  const ClassMapObject& add(const VolumeObjectResult& object);
  const std::vector<ClassMapObject>& objects() const { return objects_; }
  std::uint8_t value_of(std::uint32_t id) const;  // 0 for an id that was not added (a dropped object)

 private:
  ClassMapLegend legend_;
  std::vector<ClassMapObject> objects_;  // ascending id
};

// The class map's voxels, read from the objects' ids in the image (no second volume is made).
LabelRowSource class_map_source(const volume::LabelImage& image, const volume::ObjectSet& objects, const ClassMap& map);

// NGFF "image-label" metadata (JSON text): a colour and the class name per value, and per value the objects that
// carry it (label id, class, probability, margin, novel, error code); the source image two levels up.
std::string ngff_image_label_json(const ClassMap& map);

// Written in the format of `read` (format by input): NIfTI (gzipped when `path` ends .gz), TIFF, or an OME-Zarr
// labels/<name> group in the store directory `path` (created, or the input store itself: beside its labels).
void write_class_map(const std::filesystem::path& path, const std::string& name, const VolumeReadResult& read,
                     const volume::ObjectSet& objects, const ClassMap& map);

// The same as bytes for an HTTP answer: .nii.gz, .tif, or the zip of the store holding labels/<name>.
struct ClassMapBytes {
  std::string bytes;
  std::string media_type;  // application/gzip, image/tiff, application/zip
  std::string extension;   // ".nii.gz", ".tif", ".ome.zarr.zip"
};
ClassMapBytes class_map_bytes(const std::string& name, const VolumeReadResult& read, const volume::ObjectSet& objects,
                              const ClassMap& map);

}  // namespace wish
