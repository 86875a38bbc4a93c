#pragma once
// Where `wish predict --out-labels OUT [--table T.csv]` writes (cli/cmd_predict.cpp): one input volume: its class map
// at OUT itself (a file for NIfTI and TIFF, a zarr store directory for OME-Zarr: the input store itself puts it
// beside the input's labels); several: OUT is a directory holding <stem>_<model><ext> per volume. The run's table
// (core/pipeline/object_table.hpp) goes to T.csv and T.h5ad, by default beside the class map as <OUT stem>.objects.csv
// (one volume) or OUT/objects.csv (several).

#include <filesystem>
#include <string>

#include "cli/volume_options.hpp"
#include "core/io/volume_io.hpp"

namespace wish::cli {

inline const char* class_map_extension(VolumeFormat format) {
  return format == VolumeFormat::Nifti ? ".nii.gz" : format == VolumeFormat::Tiff ? ".tif" : ".zarr";
}

inline std::filesystem::path class_map_path(const std::string& out, const std::string& input, VolumeFormat format,
                                            const std::string& name, bool several) {
  if (!several) return out;
  return std::filesystem::path(out) / (volume_stem(input) + "_" + name + class_map_extension(format));
}

inline std::filesystem::path table_path(const std::string& out, const std::string& table, bool several) {
  if (!table.empty()) return table;
  if (several) return std::filesystem::path(out) / "objects.csv";
  std::filesystem::path p(out);
  if (!p.has_filename()) p = p.parent_path();
  return p.parent_path() / (volume_stem(p.string()) + ".objects.csv");
}

}  // namespace wish::cli
