// `wish mesh-labels VOL... --out DIR [--spacing x,y,z --unit nm] [--min-voxels N] [--drop-truncated] ...`:
// one closed genus-0 mesh per object of each label volume (DIR/<volume>_<label>.ply) and DIR/objects.csv with one
// row per object: volume, label id, voxel count, centroid, bounding box, truncated, genus, status (meshed / refused /
// dropped) and the reason, the surface's size, area and volume against the voxel object's, repairs and stage
// timings, and the fragments merged into it and the handle repair kept (method, volume change). Objects a filter
// dropped (specks, ...) are rows with status dropped and their reason.
// A progress line on stderr counts the objects. Exit status 1 when a volume could not be read or an object was
// refused (the others are still written). What the volume's values were taken for (labels, mask, mask with soft
// edges, probability map; the threshold and why) is a stderr line and the input_kind / threshold columns.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/command_registry.hpp"
#include "cli/file_bytes.hpp"
#include "cli/input_decision_text.hpp"
#include "cli/volume_options.hpp"
#include "cli/volume_rows.hpp"
#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/pipeline/object_table.hpp"
#include "core/pipeline/volume_description.hpp"

namespace wish::cli::mesh_labels_command {  // one namespace per command: the commands compile in one unity batch
namespace {

struct MeshLabelsOptions {
  std::vector<std::string> files;
  std::string out;
  std::string format = "ply";
  bool quiet = false;
  VolumeCliOptions volume;
};


std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

int run(const MeshLabelsOptions& o) {
  namespace fs = std::filesystem;
  fs::create_directories(o.out);
  std::ofstream csv(fs::path(o.out) / "objects.csv");
  csv << "volume,label_id,voxel_count,centroid_x,centroid_y,centroid_z,bbox_min_x,bbox_min_y,bbox_min_z,bbox_max_x,"
         "bbox_max_y,bbox_max_z,truncated,genus,status,reason,file,vertices,faces,mesh_area,mesh_volume,voxel_volume,"
         "volume_ratio,raw_area,unit,repairs,t_extraction,t_surface,t_smoothing,t_decimation,input_kind,threshold,"
         "fragments,repair,volume_change\n";
  const VolumeOptions options = to_volume_options(o.volume);
  bool all_ok = true;
  for (const std::string& file : o.files) {
    const std::string stem = volume_stem(file);
    std::size_t total = 0, meshed = 0, refused = 0;
    std::string unit, input_kind, threshold;
    try {
      const std::string bytes = read_volume_input(file, options.read);  // a zarr store directory: its zip
      std::string out_file;  // of the object being written
      const VolumeSummary summary = describe_volume(
          bytes, options,
          [&](const volume::VolumeObject& obj, Mesh mesh) -> std::optional<PipelineResult> {  // the work: write it
            out_file = stem + "_" + std::to_string(obj.id) + "." + o.format;
            write_mesh_file(mesh, fs::path(o.out) / out_file);
            return std::nullopt;
          },
          [&](std::size_t i, VolumeObjectResult& r) {
            const volume::VolumeObject& obj = r.object;
            const SurfaceFigures& s = r.surface;
            if (r.ok()) {
              ++meshed;
            } else {
              ++refused;
              all_ok = false;
              out_file.clear();
            }
            std::string repairs;
            for (const auto& rep : s.repairs) repairs += (repairs.empty() ? "" : "; ") + rep;
            csv << csv_field(stem) << ',' << obj.id << ',' << obj.voxel_count << ',' << num(obj.centroid(0)) << ','
                << num(obj.centroid(1)) << ',' << num(obj.centroid(2)) << ',' << obj.bbox_min[0] << ',' << obj.bbox_min[1]
                << ',' << obj.bbox_min[2] << ',' << obj.bbox_max[0] << ',' << obj.bbox_max[1] << ',' << obj.bbox_max[2]
                << ',' << (obj.truncated ? "true" : "false") << ',' << s.genus << ',' << (r.ok() ? "meshed" : "refused")
                << ',' << csv_field(r.ok() ? "" : r.error->code() + ": " + r.error->what()) << ','
                << csv_field(out_file) << ',' << s.vertices << ',' << s.faces << ',' << num(s.area) << ','
                << num(s.volume) << ',' << num(s.voxel_volume) << ','
                << num(s.voxel_volume > 0 && r.ok() ? s.volume / s.voxel_volume : 0) << ',' << num(s.raw_area) << ','
                << csv_field(unit) << ',' << csv_field(repairs) << ',' << num(s.timings.extraction) << ','
                << num(s.timings.surface) << ',' << num(s.timings.smoothing) << ',' << num(s.timings.decimation)
                << ',' << input_kind << ',' << threshold << ',' << obj.fragments.size() << ','
                << (s.genus > 0 && s.repaired ? s.repair.method() : "none") << ','
                << num(s.genus > 0 && s.repaired ? s.repair.volume_change() : 0) << '\n';
            out_file.clear();
            if (!o.quiet)
              std::cerr << "\r" << stem << ": object " << (i + 1) << "/" << total << " (label " << obj.id << "), "
                        << meshed << " meshed, " << refused << " refused   " << std::flush;
          },
          Deadline{},
          [&](const VolumeSummary& summary) {
            total = static_cast<std::size_t>(summary.kept);
            unit = summary.unit;
            input_kind = volume::to_string(summary.input.kind);
            threshold = threshold_text(summary.input);
            if (!o.quiet) print_volume_counts(std::cerr, stem, summary);
            print_input_decision(std::cerr, stem, summary.input, o.quiet);
          });
      if (!o.quiet) std::cerr << "\n";
      // Every object a filter dropped is a row too, with its reason: never dropped silently.
      for (const volume::DroppedObject& d : summary.dropped) {
        const volume::VolumeObject& obj = d.object;
        csv << csv_field(stem) << ',' << obj.id << ',' << obj.voxel_count << ',' << num(obj.centroid(0)) << ','
            << num(obj.centroid(1)) << ',' << num(obj.centroid(2)) << ',' << obj.bbox_min[0] << ',' << obj.bbox_min[1]
            << ',' << obj.bbox_min[2] << ',' << obj.bbox_max[0] << ',' << obj.bbox_max[1] << ',' << obj.bbox_max[2]
            << ',' << (obj.truncated ? "true" : "false") << ",,dropped," << csv_field(std::string(volume::to_string(d.reason)) + ": " + d.why)
            << ",,,,,,,,," << csv_field(unit) << ",,,,,," << input_kind << ',' << threshold << ','
            << obj.fragments.size() << ",,\n";
      }
    } catch (const WishError& e) {
      all_ok = false;
      std::cerr << "\n" << file << ": error [" << e.code() << "] " << e.what() << "\n";
    }
  }
  return all_ok ? kExitOk : kExitInvalid;
}

CommandRunner setup(CLI::App& sub) {
  auto o = std::make_shared<MeshLabelsOptions>();
  sub.add_option("volumes", o->files, "Label volumes (NIfTI-1 .nii/.nii.gz, TIFF stacks, OME-Zarr stores or their .zip)")->required();
  sub.add_option("--out", o->out, "Output directory (meshes and objects.csv)")->required();
  sub.add_option("--format", o->format, "Mesh format")->check(CLI::IsMember({"ply", "obj", "off", "stl"}))->capture_default_str();
  sub.add_flag("--quiet", o->quiet, "No progress line");
  add_volume_options(sub, o->volume);
  return [o]() { return run(*o); };
}

const bool registered = register_command({"mesh-labels", "One closed genus-0 mesh per object of a label volume", &setup, 25});

}  // namespace
}  // namespace wish::cli::mesh_labels_command
