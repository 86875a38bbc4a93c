#pragma once
// One table of every object of a run's label volumes (issue 39): one row per object, kept or dropped, for analysis
// in Python or R. Written as CSV always and as AnnData (.h5ad: X the descriptors, obs these rows, var the feature
// names; core/io/h5ad_writer.hpp).
// Columns (obs), in order:
//   file, label_id, status (classified | novel | refused | dropped), reason (the error's code and message, or why
//   the object was dropped), class, class_value (its value in the class map, class_map.hpp; 0 for a dropped one),
//   probability (of the class), margin, novel (true / false / empty: not computed), novelty_score,
//   novelty_p_value, p_<class> per class, voxel_count, centroid_x/y/z (physical units), bbox_min_x/y/z and
//   bbox_max_x/y/z (voxel indices), truncated, fragments (pieces merged into it), genus_before, repair (cut | fill
//   | cut_and_fill | none), volume_change (of the repair, a share), area, volume, voxel_volume (the surface's,
//   in the volume's unit), unit.
// Features (X; CSV columns after the rest): xi_0 .. xi_L, then g_<name> of the global descriptors when the model
// uses them; empty (NaN in X) for an object that was not described.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/io/h5ad_writer.hpp"
#include "core/pipeline/class_map.hpp"

namespace wish {

// A CSV field (RFC 4180): quoted, with doubled quotes, when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& text);

class ObjectTable {
 public:
  explicit ObjectTable(std::vector<std::string> classes) : classes_(std::move(classes)) {}

  // A kept object: `value` is its class map value (class_map.hpp).
  void add(const std::string& file, const std::string& unit, const VolumeObjectResult& object, std::uint8_t value,
           const ClassMapLegend& legend);
  // Every object a filter dropped, with its reason.
  void add_dropped(const std::string& file, const std::string& unit, const volume::DroppedObject& dropped);

  std::size_t size() const { return rows_.size(); }
  std::string csv() const;
  AnnDataTable anndata() const;
  // CSV at `csv_path`, and AnnData at the same path with the extension .h5ad.
  void write(const std::filesystem::path& csv_path) const;

 private:
  struct Row {
    std::string file;
    std::uint32_t label_id = 0;
    std::string status, reason, label;
    int value = 0;
    double probability = std::numeric_limits<double>::quiet_NaN(), margin = std::numeric_limits<double>::quiet_NaN();
    std::optional<bool> novel;
    double novelty_score = std::numeric_limits<double>::quiet_NaN(), novelty_p_value = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> probabilities;  // per class, empty when not classified
    volume::VolumeObject object;
    int genus = -1;
    std::string repair = "none";
    double volume_change = 0;
    double area = std::numeric_limits<double>::quiet_NaN(), volume = std::numeric_limits<double>::quiet_NaN(),
           voxel_volume = std::numeric_limits<double>::quiet_NaN();
    std::string unit;
    std::vector<double> xi, global;  // empty when not described
  };
  std::vector<std::string> feature_names() const;

  std::vector<std::string> classes_;
  std::vector<Row> rows_;
};

}  // namespace wish
