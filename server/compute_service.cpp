#include "server/compute_service.hpp"

#include "core/common/error_codes.hpp"

#include "core/pipeline/pipeline.hpp"
#include "core/pipeline/volume_pipeline.hpp"
#include "server/api_response.hpp"
#include "server/loaded_model.hpp"
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
  if (params.lmax && *params.lmax != ds.sh.lmax)
    mismatch("lmax", std::int64_t{*params.lmax}, std::int64_t{ds.sh.lmax}, std::to_string(*params.lmax),
             std::to_string(ds.sh.lmax));
  const std::string model_method = to_string(ds.map.method);
  if (params.method && *params.method != model_method)
    mismatch("method", *params.method, model_method, *params.method, model_method);
  if (params.steps && *params.steps != model_steps(ds))
    mismatch("steps", std::int64_t{*params.steps}, std::int64_t{model_steps(ds)}, std::to_string(*params.steps),
             std::to_string(model_steps(ds)));
}

namespace {

// Reading limits, reconstruction and the JSON parts every job shares.
PipelineOptions base_options(const ComputeJob& job, const ServerConfig& config) {
  PipelineOptions options;
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
  if (job.params.lmax) options.sh.lmax = *job.params.lmax;
  if (job.params.method) options.map.method = map_method_from_name(*job.params.method);
  if (job.params.steps) {
    if (options.map.method == MapMethod::Cmcf) options.map.cmcf.max_steps = *job.params.steps;
    else options.map.willmore.max_steps = *job.params.steps;
  }
  const int steps = options.map.method == MapMethod::Cmcf ? options.map.cmcf.max_steps : options.map.willmore.max_steps;
  json_options.settings = settings_used(job.params.explicit_descriptor() ? "request" : "default", options.sh.lmax,
                                        options.map.method, steps, options.sh);
}

void apply_model_settings(const ComputeJob& job, ResultJsonOptions& json_options) {
  const ClassifierModel& model = job.model->model;
  const auto& ds = model.recipe();
  json_options.settings = settings_used("model", ds.sh.lmax, ds.map.method, model_steps(ds), ds.sh);
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

VolumeOptions volume_options(const ComputeJob& job, const ServerConfig& config) {
  const VolumeParams& p = job.params.volume;
  VolumeOptions v;
  v.read.limits.max_bytes = config.max_upload_bytes;
  v.read.limits.max_voxels = config.max_volume_voxels;
  if (p.spacing) v.read.spacing_override = Eigen::Vector3d((*p.spacing)[0], (*p.spacing)[1], (*p.spacing)[2]);
  if (p.unit) v.read.unit_override = *p.unit;
  v.objects.mode = p.objects == "labels"       ? volume::ObjectMode::Labels
                   : p.objects == "components" ? volume::ObjectMode::Components
                                               : volume::ObjectMode::Auto;
  v.objects.min_voxels = p.min_voxels;
  v.objects.drop_truncated = p.drop_truncated;
  v.objects.label_ids = p.labels;
  v.objects.max_objects = config.max_volume_objects;
  v.surface.max_box_voxels = config.max_object_box_voxels;
  return v;
}

// The refusal of a volume with no object to describe (every voxel background, or every object filtered out): a
// 422 that says which filter took them, rather than a 200 with an empty list that a batch script reads as success.
WishError no_objects_error(const VolumeSummary& s) {
  std::string why = s.found == 0 ? "every voxel is background (0)"
                                 : std::to_string(s.found) + " found, dropped: " +
                                       std::to_string(s.dropped_not_selected) + " not in labels, " +
                                       std::to_string(s.dropped_small) + " under min_voxels, " +
                                       std::to_string(s.dropped_truncated) + " truncated (drop_truncated)";
  return WishError(ErrorCategory::Unmappable, "no_objects", "the label volume has no object to describe: " + why,
                   {{"objects_found", s.found}, {"not_selected", s.dropped_not_selected},
                    {"small", s.dropped_small}, {"truncated", s.dropped_truncated}});
}

// A label volume: every kept object is meshed (core/pipeline/volume_pipeline.hpp) and described or classified like
// an uploaded mesh; an object that cannot be is an error entry with its own status, the others are unaffected.
// The volume's own status follows its objects' as a batch's follows its parts' (batch_status): 200 all described,
// their common status when all were refused alike, 207 when they differ; `out.error` is the first refusal.
// The time limit covers the whole volume: past it, or when cancelled, the part fails (504 / 503) as a mesh would.
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
  std::vector<int> statuses;  // of the objects, in order
  const auto add = [&](nlohmann::json&& entry, int status) {
    entry["status"] = status;
    statuses.push_back(status);
    objects.push_back(std::move(entry));
  };
  const auto refuse = [&](nlohmann::json&& entry, const ApiError& error) {
    entry["error"] = error_object(error);
    if (refused++ == 0) out.error = error;
    add(std::move(entry), error.status);
  };
  const VolumeSummary summary = for_each_object_surface(
      *job.part.bytes, volume_options(job, config),
      [&](std::size_t index, const volume::VolumeObject& object, volume::ObjectSurface& surface) {
        if (job.deadline.expired()) {
          try {
            job.deadline.check("label volume objects");
          } catch (const WishError& e) {
            if (e.code() == "cancelled") throw;  // 503 "cancelled"; a timeout is reported with the count below
          }
          throw TimeoutError("time limit exceeded after " + std::to_string(index) + " of " + std::to_string(kept) +
                                 " objects of the label volume",
                             {{"stage", std::string("label volume objects")},
                              {"objects_done", static_cast<std::int64_t>(index)}, {"objects", kept},
                              {"limit_seconds", config.volume_time_limit_seconds}});
        }
        nlohmann::json entry{{"label_id", object.id}, {"object", volume_object_json(object, surface)}};
        out.stages["surface"] += surface.timings.extraction + surface.timings.surface + surface.timings.smoothing +
                                 surface.timings.decimation;
        if (!surface.ok) {
          // The category (so the status) the code table gives the refusal: 413 for box_too_large, 422 for a
          // surface that is not genus 0, ...
          const ErrorCodeInfo* info = find_error_code(surface.refusal_code);
          const ErrorCategory category =
              info && info->category ? *info->category : ErrorCategory::Unmappable;
          const ApiError error = to_api_error(WishError(category, surface.refusal_code,
                                                        surface.refusal, {{"label_id", std::int64_t{object.id}},
                                                                          {"genus", std::int64_t{surface.genus}}}));
          refuse(std::move(entry), error);
          return;
        }
        try {
          PipelineResult result = describe_mesh(std::move(surface.mesh), options, job.deadline);
          if (job.op == Operation::Classify) {
            const auto t = std::chrono::steady_clock::now();
            classify_described(result, job.model->model, PredictOptions{options.novelty_quantile});
            result.timings.classify = seconds_between(t, std::chrono::steady_clock::now());
            result.timings.total += result.timings.classify;
          }
          record_stages(job, result.timings, out);
          vertices += result.prepared.input_report.vertices;
          faces += result.prepared.input_report.faces;
          entry["result"] = result_json(result, json_options);
          entry["result"]["request_id"] = job.request_id;
          ++described;
          add(std::move(entry), 200);
        } catch (const WishError& e) {
          // The request's own limit or cancellation ends the whole volume; anything else is this object's refusal.
          if (e.category() == ErrorCategory::Timeout || e.code() == "cancelled") throw;
          refuse(std::move(entry), to_api_error(e));
        }
      },
      [&](const VolumeSummary& s) { kept = s.kept; });
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
}

}  // namespace

ComputeOutcome run_compute(const ComputeJob& job, const ServerConfig& config) noexcept {
  ComputeOutcome out;
  const auto started = std::chrono::steady_clock::now();
  out.stages["queue_wait"] = seconds_between(job.submitted, started);
  try {
    job.deadline.check("queue wait");  // expired while queued: do not start
    if (!job.part.volume && !job.params.volume.given.empty())
      throw InvalidInputError("invalid_parameter",
                              "parameter '" + job.params.volume.given.front() +
                                  "' applies to label volumes (NIfTI-1, TIFF) only; this part is a mesh",
                              {{"parameter", job.params.volume.given.front()}});
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
