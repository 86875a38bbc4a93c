#include "server/compute_service.hpp"

#include "core/pipeline/pipeline.hpp"
#include "server/loaded_model.hpp"
#include "server/result_json.hpp"

namespace wish::server {

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

ComputeOutcome run_compute(const ComputeJob& job, const ServerConfig& config) noexcept {
  ComputeOutcome out;
  const auto started = std::chrono::steady_clock::now();
  out.stages["queue_wait"] = seconds_between(job.submitted, started);
  try {
    job.deadline.check("queue wait");  // expired while queued: do not start

    PipelineOptions options;
    options.read.limits.max_bytes = config.max_upload_bytes;
    options.read.limits.max_vertices = config.max_vertices;
    options.read.limits.max_faces = config.max_faces;
    options.read.hint = format_from_name(format_hint(job.params, job.part));
    if (job.params.include_reconstruction) options.reconstruction_level = job.params.reconstruction_level;

    ResultJsonOptions json_options;
    json_options.coefficients = job.params.include_coefficients;
    json_options.invariants = job.params.include_invariants;
    json_options.quality = job.params.include_quality;
    json_options.reconstruction = job.params.include_reconstruction;
    json_options.reconstruction_level = job.params.reconstruction_level;
    json_options.mesh = job.params.include_mesh;
    json_options.sphere = job.params.include_sphere;
    json_options.distortion = job.params.include_distortion;
    json_options.filename = job.part.filename;
    json_options.bytes = job.part.bytes->size();

    PipelineResult result;
    if (job.op == Operation::Classify) {
      const ClassifierModel& model = job.model->model;
      const auto& ds = model.recipe();
      json_options.settings = settings_used("model", ds.sh.lmax, ds.map.method, model_steps(ds), ds.sh);
      json_options.model_name = model.name();
      json_options.model_version = model.version();
      result = classify_mesh_bytes(*job.part.bytes, model, options, job.deadline);
    } else {
      if (job.params.lmax) options.sh.lmax = *job.params.lmax;
      if (job.params.method) options.map.method = map_method_from_name(*job.params.method);
      if (job.params.steps) {
        if (options.map.method == MapMethod::Cmcf) options.map.cmcf.max_steps = *job.params.steps;
        else options.map.willmore.max_steps = *job.params.steps;
      }
      const int steps = options.map.method == MapMethod::Cmcf ? options.map.cmcf.max_steps
                                                              : options.map.willmore.max_steps;
      json_options.settings = settings_used(job.params.explicit_descriptor() ? "request" : "default", options.sh.lmax,
                                            options.map.method, steps, options.sh);
      result = describe_mesh_bytes(*job.part.bytes, options, job.deadline);
    }
    out.vertices = result.prepared.input_report.vertices;
    out.faces = result.prepared.input_report.faces;
    const auto& t = result.timings;
    out.stages["read"] = t.read;
    out.stages["validate"] = t.validate;
    out.stages["map"] = t.map;
    out.stages["fit"] = t.fit;
    if (job.op == Operation::Classify) out.stages["classify"] = t.classify;
    out.stages["total"] = t.total;
    out.result = result_json(result, json_options);
    out.result["timings"]["queue_wait"] = out.stages["queue_wait"];
    out.status = 200;
  } catch (...) {
    out.error = to_api_error(std::current_exception());
    out.status = out.error.status;
  }
  return out;
}

}  // namespace wish::server
