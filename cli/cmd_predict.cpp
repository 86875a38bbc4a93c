// `wish predict --model M FILE... [--json|--csv]`: label, class probabilities (Platt) and decision margin per
// mesh, computed with the model's own descriptor settings (core/pipeline classify_mesh_bytes). A file that fails
// is reported and the others still run; exit status 1 then. A label volume (NIfTI-1, TIFF; by content; the volume
// options of `wish mesh-labels`) gives one result per kept object, keyed by label id (JSON "label_id" and an
// "object" block; CSV column label_id, empty for meshes); a refused object is a row with its error.
// `--out-labels OUT` writes each volume's class map (core/pipeline/class_map.hpp) in the input's format and
// `--table T.csv` (default beside it) one table of every object, kept or dropped, as CSV and AnnData (.h5ad).
// `wish predict --model M --descriptors D.csv`: the same from descriptors already computed (`wish describe --csv`,
// `wish train --save-descriptors`), one result per row. The table's Lmax must be the model's: ξ(l) of a fit at
// another Lmax are not the model's features, so a mismatch is refused, never predicted from.
#include <iomanip>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/class_map_paths.hpp"
#include "cli/command_registry.hpp"
#include "wire/error_json.hpp"
#include "wire/wire_json.hpp"
#include "cli/file_bytes.hpp"
#include "cli/volume_options.hpp"
#include "cli/volume_rows.hpp"
#include "core/classify/classifier_model.hpp"
#include "core/common/errors.hpp"
#include "core/pipeline/class_map.hpp"
#include "core/pipeline/object_table.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/training/descriptor_table.hpp"
#include "wire/volume_result_json.hpp"

namespace wish::cli::predict_command {  // one namespace per command: the commands compile in one unity batch
namespace {

struct PredictOptions {
  std::string model;
  std::vector<std::string> files;
  std::string descriptors;
  bool json = false, csv = false, quiet = false;
  double novelty_quantile = 0;  // 0: the model's own
  VolumeCliOptions volume;
  std::string out_labels, table;  // the class map(s) and the run's table (cli/class_map_paths.hpp)
};

// The legend of a class map on stderr: value, class and colour, so a viewer's colours can be read.
void print_legend(std::ostream& os, const ClassMapLegend& legend) {
  os << "class map values: 0 background (and dropped specks)";
  for (const auto& e : legend.entries)
    os << "; " << static_cast<int>(e.value) << " " << e.name << " (rgb " << static_cast<int>(e.rgb[0]) << ","
       << static_cast<int>(e.rgb[1]) << "," << static_cast<int>(e.rgb[2]) << ")";
  os << "\n";
}

std::string row_name(const nlohmann::json& r) {
  std::string name = r["file"].get<std::string>();
  if (r.contains("label_id")) name += "#" + std::to_string(r["label_id"].get<std::uint32_t>());
  return name;
}

// The probability of class `c` in a row's prediction (wire: an array of {label, probability} in class order).
double probability_of(const nlohmann::json& row, const std::string& c) {
  for (const auto& p : row["probabilities"])
    if (p["label"] == c) return p["probability"].get<double>();
  return 0;
}


CommandRunner setup_predict(CLI::App& sub) {
  auto o = std::make_shared<PredictOptions>();
  sub.add_option("--model", o->model, "Model file written by `wish train` (e.g. data/models/default.json)")->required();
  auto* files = sub.add_option("files", o->files, "Mesh files (OBJ, PLY, OFF, STL) or label volumes (NIfTI-1, TIFF, OME-Zarr store or .zip)");
  sub.add_option("--descriptors", o->descriptors,
                 "Descriptor CSV (xi_0..xi_L columns, as `wish describe --csv` writes) instead of mesh files")
      ->excludes(files);
  auto* json = sub.add_flag("--json", o->json, "JSON array, one object per file");
  sub.add_flag("--csv", o->csv, "CSV: file, label_id, label, margin, novel, novelty_score, novelty_p_value, p_<class>...")
      ->excludes(json);
  sub.add_option("--novelty-quantile", o->novelty_quantile,
                 "Flag a sample novel (none of the known types) when its novelty score against every class is above this "
                 "quantile of that class's calibration scores (leave-one-out, or cross-validated in a model trained with --novelty-folds) (0: the model's own, 0.99 by default)")
      ->check(CLI::Range(0.0, 0.999999))->capture_default_str();
  sub.add_flag("--quiet", o->quiet, "No progress line for label volumes");
  sub.add_option("--out-labels", o->out_labels,
                 "Label volumes: write a class map, each object's voxels carrying its class (1..K in the model's class "
                 "order, K+1 novel, K+2 refused, 0 background), in the input's format: NIfTI or TIFF file, or an "
                 "OME-Zarr store directory receiving labels/<model name>; a directory for several volumes")
      ->excludes("--descriptors");
  sub.add_option("--table", o->table,
                 "Label volumes: one table of every object (kept or dropped) as CSV at this path and AnnData beside it "
                 "(.h5ad); default with --out-labels: <OUT stem>.objects.csv")
      ->excludes("--descriptors");
  add_volume_options(sub, o->volume);
  return [o]() {
    const ClassifierModel model = ClassifierModel::load(o->model);
    if (o->files.empty() && o->descriptors.empty())
      throw InvalidInputError("invalid_parameter", "give mesh files or --descriptors CSV");
    bool ok = true;
    nlohmann::json results = nlohmann::json::array();
    const wish::PredictOptions predict_options{o->novelty_quantile};
    // One encoder of a prediction (wire/wire_json.hpp, the service's): label, probabilities, margin, model, novel,
    // novelty and, when the recipe check ran, recipe_match / method_used / recipe_method; merged into the row.
    auto record = [&](nlohmann::json& r, const Prediction& p, const std::optional<RecipeConformance>& recipe) {
      r.update(wire::prediction_json(p, model.name(), model.version(), recipe));
    };
    auto fail = [&](nlohmann::json& r, const std::string& what, const WishError& e) {
      ok = false;
      r["error"] = wire::error_entry_json(e);  // the shape of every CLI error row: code, category, message, details
      if (!o->json) std::cerr << "wish predict: " << what << ": error [" << e.code() << "] " << e.what() << "\n";
    };
    if (!o->descriptors.empty()) {
      const DescriptorTable table = read_unlabelled_descriptor_table(read_file_bytes(o->descriptors));
      const int model_lmax = model.recipe().sh.lmax;
      if (table.lmax != model_lmax)
        throw InvalidInputError("descriptor_mismatch",
                                "the descriptor CSV has xi_0..xi_" + std::to_string(table.lmax) + " but model '" +
                                    model.name() + "' was trained on fits with Lmax " + std::to_string(model_lmax) +
                                    "; describe the meshes with --lmax " + std::to_string(model_lmax));
      if (model.needs_global_features() && !table.has_global)
        throw InvalidInputError("descriptor_mismatch", "model '" + model.name() +
                                                           "' needs the global shape descriptors (g_* columns), which "
                                                           "the CSV lacks; write it with `wish train --save-descriptors`");
      for (const TrainingSample& sample : table.samples) {
        nlohmann::json r = {{"file", sample.id}};
        try {
          record(r, model.predict(sample.features, predict_options), std::nullopt);
        } catch (const WishError& e) {
          fail(r, sample.id, e);
        }
        results.push_back(r);
      }
    }
    auto classified = [&](nlohmann::json& r, const PipelineResult& res) {
      record(r, res.prediction.value(), res.recipe);
      r["seconds"] = res.timings.total;
    };
    const VolumeOptions volume = to_volume_options(o->volume);
    std::vector<nlohmann::json> rows;
    nlohmann::json volumes = nlohmann::json::array();  // per volume: what was read, and every object dropped
    const bool writes_maps = !o->out_labels.empty(), writes_table = writes_maps || !o->table.empty();
    const bool several = o->files.size() > 1;
    if (writes_maps && several) std::filesystem::create_directories(o->out_labels);
    const ClassMapLegend legend = class_map_legend(model.classes());
    const std::string map_name = class_map_name(model.name());
    ObjectTable table(model.classes());
    if (writes_maps && !o->quiet) print_legend(std::cerr, legend);
    for (const auto& file : o->files) {
      nlohmann::json r = {{"file", file}};
      try {
        const std::string bytes = read_volume_input(file, volume.read);  // a zarr store directory: its zip
        if (detect_volume_format(bytes) != VolumeFormat::Unknown) {  // a label volume: one row per kept object
          const PipelineOptions po = options_for_recipe(model.recipe());
          ClassMap map(legend);
          std::string unit;
          VolumeRowHooks hooks;
          hooks.summary = [&](const VolumeSummary& s) {
            unit = s.unit;
            volumes.push_back({{"file", file}, {"volume", wire::volume_summary_json(s)}});
            if (writes_table)
              for (const volume::DroppedObject& d : s.dropped) table.add_dropped(file, unit, d);
          };
          hooks.object = [&](const VolumeObjectResult& object, nlohmann::json& row) {
            const ClassMapObject& entry = map.add(object);
            row["class_value"] = entry.value;
            if (writes_table) table.add(file, unit, object, entry.value, legend);
          };
          if (writes_maps)
            hooks.complete = [&](const VolumeReadResult& read, const volume::ObjectSet& objects) {
              const auto path = class_map_path(o->out_labels, file, read.format, map_name, several);
              write_class_map(path, map_name, read, objects, map);
              if (!o->quiet)
                std::cerr << file << ": class map " << path.string()
                          << (read.format == VolumeFormat::OmeZarr ? " (labels/" + map_name + ")" : std::string())
                          << "\n";
            };
          volume_rows(file, bytes, volume, !o->quiet,
                      [&](const volume::VolumeObject&, Mesh mesh) -> std::optional<PipelineResult> {
                        PipelineResult res = describe_mesh(std::move(mesh), po);
                        classify_described(res, model, predict_options);
                        return res;
                      },
                      classified, [&](nlohmann::json& row, const WishError& e) { fail(row, row_name(row), e); },
                      rows, hooks);
          for (auto& row : rows) results.push_back(std::move(row));
          rows.clear();
          continue;
        }
        PipelineOptions po;
        po.novelty_quantile = o->novelty_quantile;
        const auto dot = file.find_last_of('.');
        if (dot != std::string::npos) po.read.hint = format_from_name(file.substr(dot));
        classified(r, classify_mesh_bytes(bytes, model, po));
      } catch (const WishError& e) {
        fail(r, file, e);
      }
      results.push_back(r);
    }
    if (writes_table) {
      const auto path = table_path(o->out_labels, o->table, several);
      table.write(path);
      if (!o->quiet)
        std::cerr << "table of " << table.size() << " objects: " << path.string() << " and .h5ad beside it\n";
    }
    const auto& classes = model.classes();
    if (o->json) {
      nlohmann::json doc = {{"model", {{"name", model.name()}, {"version", model.version()},
                                       {"sha256", model.payload_sha256()}, {"classes", classes}}},
                            {"predictions", results},
                            {"volumes", volumes}};
      if (writes_maps) {
        nlohmann::json values = nlohmann::json::array();
        for (const auto& e : legend.entries)
          values.push_back({{"value", e.value}, {"name", e.name}, {"rgb", {e.rgb[0], e.rgb[1], e.rgb[2]}}});
        doc["class_map"] = {{"name", map_name}, {"values", values}};
      }
      std::cout << doc.dump(2) << "\n";
    } else if (o->csv) {
      std::cout << "file,label_id,label,margin,novel,novelty_score,novelty_p_value";
      for (const auto& c : classes) std::cout << ",p_" << c;
      std::cout << ",novelty_nearest_class,novelty_distance_ratio";
      std::cout << "\n" << std::setprecision(10);
      for (const auto& r : results) {
        if (r.contains("error")) continue;
        std::cout << csv_field(r["file"].get<std::string>()) << ","
                  << (r.contains("label_id") ? std::to_string(r["label_id"].get<std::uint32_t>()) : "") << ","
                  << csv_field(r["label"].get<std::string>()) << ","
                  << r["margin"].get<double>() << ",";
        // Empty novelty cells: the model has no novelty calibration.
        if (r["novel"].is_boolean()) {
          std::cout << (r["novel"].get<bool>() ? "true" : "false") << "," << r["novelty"]["score"].get<double>() << ","
                    << r["novelty"]["p_value"].get<double>();
        } else {
          std::cout << ",,";
        }
        for (const auto& c : classes) std::cout << "," << probability_of(r, c);
        // Why: the class the sample is most like and its distance in units of that class's spread (empty without).
        const bool why = r.contains("novelty") && r["novelty"].contains("nearest_class");
        std::cout << "," << (why ? csv_field(r["novelty"]["nearest_class"].get<std::string>()) : "") << ",";
        if (why) std::cout << wire::json_number_or_nan(r["novelty"]["distance_ratio"]);
        std::cout << "\n";
      }
    } else {
      for (const auto& r : results) {
        if (r.contains("error")) continue;
        std::cout << row_name(r) << ": " << r["label"].get<std::string>() << "  (margin "
                  << std::setprecision(3) << r["margin"].get<double>() << ";";
        for (const auto& c : classes)
          std::cout << " " << c << " " << std::fixed << std::setprecision(3) << probability_of(r, c);
        std::cout.unsetf(std::ios::fixed);
        std::cout << ")";
        if (r["novel"].is_boolean() && r["novel"].get<bool>())
        {
          std::cout << "  [NOVEL: unlike the training set (p = " << std::setprecision(3)
                    << r["novelty"]["p_value"].get<double>() << ")";
          if (r["novelty"].contains("nearest_class"))
            std::cout << "; nearest class " << r["novelty"]["nearest_class"].get<std::string>() << " at "
                      << std::setprecision(3) << wire::json_number_or_nan(r["novelty"]["distance_ratio"]) << "x its spread";
          std::cout << ", none of the known types?]";
        }
        if (r.contains("recipe_match") && !r["recipe_match"].get<bool>())
          std::cout << "  [off-recipe: map by " << r["method_used"].get<std::string>() << ", model's recipe "
                    << to_string(model.recipe().map.method) << "]";
        std::cout << "\n";
      }
    }
    return ok ? kExitOk : kExitInvalid;
  };
}

const bool registered = register_command(
    {"predict", "Classify meshes with a trained model: label, probabilities, margin", &setup_predict, 60});

}  // namespace
}  // namespace wish::cli::predict_command
