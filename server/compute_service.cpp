#include "server/compute_service.hpp"

#include "core/pipeline/class_map.hpp"
#include "core/pipeline/default_pipeline_options.hpp"
#include "core/pipeline/describe_overrides.hpp"
#include "core/pipeline/pipeline.hpp"
#include "core/spherical_map/flow_step_cap.hpp"
#include "core/pipeline/volume_overrides.hpp"
#include "core/pipeline/volume_pipeline.hpp"
#include "server/api_response.hpp"
#include "server/loaded_model.hpp"
#include "wire/base64.hpp"
#include "wire/result_json.hpp"
#include "wire/volume_result_json.hpp"

namespace wish::server {

using wire::ResultJsonOptions;
using wire::result_json;
using wire::volume_object_json;
using wire::volume_summary_json;

namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

nlohmann::json settings_used(const char* source, int lmax, MapMethod method, int steps, const ShFitOptions& sh) {
  return {{"source", source},
          {"lmax", lmax},
          {"method", to_string(method)},
          {"steps", steps},
          {"regularization", sh.regularization},
          {"weighting", to_string(sh.weighting)}};
}

}  // namespace

void check_descriptor_settings(const ComputeParams& params, const LoadedModel& loaded) {
  const auto& ds = loaded.model.recipe();
  const std::string& name = loaded.model.name();
  auto mismatch = [&](const std::string& parameter, const ErrorDetailValue& requested, const ErrorDetailValue& model,
                      const std::string& requested_text, const std::string& model_text) {
    throw InvalidInputError("descriptor_mismatch",
                            parameter + "=" + requested_text + " differs from model '" + name + "' (" + parameter +
                                "=" + model_text + "); omit it to use the model's descriptor settings",
                            {{"parameter", parameter}, {"requested", requested}, {"model_value", model}, {"model", name}});
  };
  const DescribeOverrides& given = params.descriptor;
  if (given.lmax && *given.lmax != ds.sh.lmax)
    mismatch("lmax", std::int64_t{*given.lmax}, std::int64_t{ds.sh.lmax}, std::to_string(*given.lmax),
             std::to_string(ds.sh.lmax));
  if (given.method && *given.method != ds.map.method) {
    const std::string requested = to_string(*given.method), model_method = to_string(ds.map.method);
    mismatch("method", requested, model_method, requested, model_method);
  }
  const int model_cap = flow_step_cap(ds.map);
  if (given.max_flow_steps && *given.max_flow_steps != model_cap)
    mismatch("steps", std::int64_t{*given.max_flow_steps}, std::int64_t{model_cap},
             std::to_string(*given.max_flow_steps), std::to_string(model_cap));
}

namespace {

// Reading limits, reconstruction and the JSON parts every job shares. A describe starts from the one default map and
// fit (core/pipeline/default_pipeline_options.hpp); a classify replaces them by the model's recipe.
PipelineOptions base_options(const ComputeJob& job, const ServerConfig& config) {
  PipelineOptions options = default_pipeline_options();
  options.read.limits.max_bytes = config.max_upload_bytes;
  options.read.limits.max_vertices = config.max_vertices;
  options.read.limits.max_faces = config.max_faces;
  options.read.hint = format_from_name(format_hint(job.params, job.part));
  if (job.params.include_reconstruction) options.reconstruction_level = job.params.reconstruction_level;
  options.novelty_quantile = config.novelty_quantile;
  return options;
}

ResultJsonOptions json_options_for(const ComputeJob& job) {
  ResultJsonOptions o;
  o.coefficients = job.params.include_coefficients;
  o.invariants = job.params.include_invariants;
  o.quality = job.params.include_quality;
  o.reconstruction = job.params.include_reconstruction;
  o.reconstruction_level = job.params.reconstruction_level;
  o.mesh = job.params.include_mesh;
  o.sphere = job.params.include_sphere;
  o.distortion = job.params.include_distortion;
  o.filename = job.part.filename;
  o.bytes = job.part.bytes->size();
  return o;
}

// Describe: the request's descriptor settings over the defaults (and the settings block that says so).
void apply_describe_settings(const ComputeJob& job, PipelineOptions& options, ResultJsonOptions& json_options) {
  apply_overrides(job.params.descriptor, options);
  json_options.settings = settings_used(job.params.explicit_descriptor() ? "request" : "default", options.sh.lmax,
                                        options.map.method, flow_step_cap(options.map), options.sh);
}

void apply_model_settings(const ComputeJob& job, ResultJsonOptions& json_options) {
  const ClassifierModel& model = job.model->model;
  const auto& ds = model.recipe();
  json_options.settings = settings_used("model", ds.sh.lmax, ds.map.method, flow_step_cap(ds.map), ds.sh);
  json_options.model_name = model.name();
  json_options.model_version = model.version();
}

void record_stages(const ComputeJob& job, const StageTimings& t, ComputeOutcome& out) {
  out.stages["read"] += t.read;
  out.stages["validate"] += t.validate;
  out.stages["map"] += t.map;
  out.stages["fit"] += t.fit;
  if (job.op == Operation::Classify) out.stages["classify"] += t.classify;
}

// The service's limits, then the request's settings (the one mapping, core/pipeline/volume_overrides.hpp).
VolumeOptions volume_options(const ComputeJob& job, const ServerConfig& config) {
  VolumeOptions v;
  v.read.limits.max_bytes = config.max_upload_bytes;
  v.read.limits.max_voxels = config.max_volume_voxels;
  v.objects.max_objects = config.max_volume_objects;
  v.surface.max_box_voxels = config.max_object_box_voxels;
  apply_overrides(job.params.volume, v);
  return v;
}

// A label volume: every kept object is meshed and described or classified like an uploaded mesh
// (core/pipeline/volume_description.hpp, the one owner of an object: a refused surface carries its code's
// category, so box_too_large is a 413 here as in the CLI); an object that cannot be is an error entry with its own
// status, the others are unaffected. The volume's own status follows its objects' as a batch's follows its parts'
// (batch_status): 200 all described, their common status when all were refused alike, 207 when they differ;
// `out.error` is the first refusal. The time limit covers the whole volume: past it, or when cancelled, the part
// fails (504 / 503) as a mesh would.
void run_volume(const ComputeJob& job, const ServerConfig& config, ComputeOutcome& out) {
  PipelineOptions options = base_options(job, config);
  ResultJsonOptions json_options = json_options_for(job);
  if (job.op == Operation::Classify) {
    apply_model_settings(job, json_options);
    options = options_for_recipe(job.model->model.recipe(), std::move(options));
  } else {
    apply_describe_settings(job, options, json_options);
  }
  nlohmann::json objects = nlohmann::json::array();
  std::int64_t kept = 0, described = 0, refused = 0, vertices = 0, faces = 0;
  std::string unit;
  std::vector<int> statuses;  // of the objects, in order
  const auto work = [&](const volume::VolumeObject&, Mesh mesh) -> std::optional<PipelineResult> {
    PipelineResult result = describe_mesh(std::move(mesh), options, job.deadline);
    if (job.op == Operation::Classify) {
      const auto t = std::chrono::steady_clock::now();
      classify_described(result, job.model->model, PredictOptions{options.novelty_quantile});
      result.timings.classify = seconds_between(t, std::chrono::steady_clock::now());
      result.timings.total += result.timings.classify;
    }
    return result;
  };
  // ?output=labels: each object's class map value as it is classified, the map itself once the volume is done.
  std::optional<ClassMap> class_map;
  if (job.params.output_labels) class_map.emplace(class_map_legend(job.model->model.classes()));
  nlohmann::json class_map_json;
  const auto on_complete = [&](const VolumeReadResult& read, const volume::ObjectSet& found) {
    if (!class_map) return;
    const std::string name = class_map_name(job.model->model.name());
    const ClassMapBytes bytes = class_map_bytes(name, read, found, *class_map);
    nlohmann::json values = nlohmann::json::array();
    for (const auto& e : class_map->legend().entries)
      values.push_back({{"value", e.value}, {"name", e.name}, {"rgb", {e.rgb[0], e.rgb[1], e.rgb[2]}}});
    std::string stem = job.part.filename.empty() ? std::string("volume") : job.part.filename;
    for (const char* ext : {".nii.gz", ".nii", ".tiff", ".tif", ".ome.zarr.zip", ".zarr.zip", ".zip"})
      if (stem.size() > std::string(ext).size() && stem.ends_with(ext)) {
        stem.resize(stem.size() - std::string(ext).size());
        break;
      }
    class_map_json = {{"name", name},
                      {"format", to_string(read.format)},
                      {"media_type", bytes.media_type},
                      {"filename", stem + "_" + name + bytes.extension},
                      {"values", values},
                      {"encoding", "base64"},
                      {"bytes", bytes.bytes.size()},
                      {"data", wire::base64_encode(bytes.bytes)}};
  };
  const auto on_object = [&](std::size_t, VolumeObjectResult& object) {
    const volume::SurfaceTimings& st = object.surface.timings;
    out.stages["surface"] += st.extraction + st.surface + st.smoothing + st.decimation;
    nlohmann::json entry{{"label_id", object.object.id}, {"object", volume_object_json(object, unit)}};
    if (class_map) entry["class_value"] = class_map->add(object).value;
    int status = 200;
    if (object.error) {
      const ApiError error = to_api_error(*object.error);
      entry["error"] = error_object(error);
      if (refused++ == 0) out.error = error;
      status = error.status;
    } else {
      const PipelineResult& result = *object.result;
      record_stages(job, result.timings, out);
      vertices += result.prepared.input_report.vertices;
      faces += result.prepared.input_report.faces;
      entry["result"] = result_json(result, json_options);
      entry["result"]["request_id"] = job.request_id;
      ++described;
    }
    entry["status"] = status;
    statuses.push_back(status);
    objects.push_back(std::move(entry));
  };
  VolumeSummary summary;
  try {
    summary = describe_volume(*job.part.bytes, volume_options(job, config), work, on_object, job.deadline,
                              [&](const VolumeSummary& s) {
                                kept = s.kept;
                                unit = s.unit;
                              },
                              on_complete);
  } catch (const WishError& e) {
    if (e.category() != ErrorCategory::Timeout) throw;
    ErrorDetails details = e.details();  // the service's limit beside the count of objects done
    details["limit_seconds"] = config.volume_time_limit_seconds;
    throw TimeoutError(e.what(), std::move(details));
  }
  if (summary.kept == 0) throw no_objects_error(summary);
  out.status = batch_status(statuses);
  out.vertices = vertices;
  out.faces = faces;
  out.stages["volume_read"] = summary.read_seconds;
  out.stages["volume_objects"] = summary.objects_seconds;
  out.result = {{"volume", volume_summary_json(summary)},
                {"objects", std::move(objects)},
                {"counts", {{"objects", kept}, {"described", described}, {"refused", refused}}},
                {"settings", json_options.settings}};
  if (!job.part.filename.empty()) out.result["volume"]["filename"] = job.part.filename;
  out.result["volume"]["bytes"] = job.part.bytes->size();
  if (job.op == Operation::Classify)
    out.result["model"] = {{"name", json_options.model_name}, {"version", json_options.model_version}};
  if (!class_map_json.is_null()) out.result["class_map"] = std::move(class_map_json);
}

}  // namespace

ComputeOutcome run_compute(const ComputeJob& job, const ServerConfig& config) noexcept {
  ComputeOutcome out;
  const auto started = std::chrono::steady_clock::now();
  out.stages["queue_wait"] = seconds_between(job.submitted, started);
  try {
    job.deadline.check("queue wait");  // expired while queued: do not start
    if (!job.part.volume && !job.params.volume_given.empty())
      throw InvalidInputError("invalid_parameter",
                              "parameter '" + job.params.volume_given.front() +
                                  "' applies to label volumes (NIfTI-1, TIFF, OME-Zarr) only; this part is a mesh",
                              {{"parameter", job.params.volume_given.front()}});
    if (job.part.volume) {
      run_volume(job, config, out);  // sets the status from the objects'
      out.stages["total"] = seconds_between(started, std::chrono::steady_clock::now());
      out.result["timings"] = {{"queue_wait", out.stages["queue_wait"]}, {"total", out.stages["total"]}};
      return out;
    }

    PipelineOptions options = base_options(job, config);
    ResultJsonOptions json_options = json_options_for(job);
    PipelineResult result;
    if (job.op == Operation::Classify) {
      apply_model_settings(job, json_options);
      result = classify_mesh_bytes(*job.part.bytes, job.model->model, options, job.deadline);
    } else {
      apply_describe_settings(job, options, json_options);
      result = describe_mesh_bytes(*job.part.bytes, options, job.deadline);
    }
    out.vertices = result.prepared.input_report.vertices;
    out.faces = result.prepared.input_report.faces;
    record_stages(job, result.timings, out);
    out.stages["total"] = result.timings.total;
    out.result = result_json(result, json_options);
    out.result["timings"]["queue_wait"] = out.stages["queue_wait"];
    out.status = 200;
  } catch (...) {
    out.error = to_api_error(std::current_exception());
    out.status = out.error.status;
    out.result = nullptr;  // failed as a whole: no result (assemble answers the plain error)
  }
  return out;
}

}  // namespace wish::server
