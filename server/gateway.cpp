#include "server/gateway.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>

#include <spdlog/spdlog.h>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"

namespace wish::server {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

ApiError shutting_down_error() {
  return to_api_error(WishError(ErrorCategory::Unavailable, "shutting_down", "the server is shutting down"));
}

Gateway::Gateway(const ServerConfig& config, ModelRegistry& models, WorkerPool& pool, Metrics& metrics,
                 CancelRegistry& cancels, ComputeFunction compute)
    : config_(config), models_(models), pool_(pool), metrics_(metrics), cancels_(cancels), compute_(std::move(compute)),
      backlog_(std::make_shared<WorkBacklog>(pool.workers())) {}

ApiResponse Gateway::health() const { return json_response(200, {{"status", "ok"}}); }

ApiResponse Gateway::ready(const std::string& request_id) const {
  const std::size_t n = models_.size();
  const bool accepting = pool_.accepting();
  const bool is_draining = draining_.load();
  if (n > 0 && accepting && !is_draining)
    return json_response(200, {{"ready", true}, {"models", n}, {"queue_depth", pool_.queue_depth()},
                               {"queue_capacity", pool_.capacity()}, {"workers", pool_.workers()}});
  const std::string reason = is_draining ? "shutting down" : n == 0 ? "no model loaded" : "the job queue is full";
  return error_response(to_api_error(WishError(ErrorCategory::Unavailable, "not_ready", "not ready: " + reason,
                                               {{"models", static_cast<std::int64_t>(n)},
                                                {"queue_depth", static_cast<std::int64_t>(pool_.queue_depth())},
                                                {"shutting_down", std::string(is_draining ? "true" : "false")}})),
                        request_id);
}

ApiResponse Gateway::metrics_text() const {
  Gauges g;
  g.queue_depth = pool_.queue_depth();
  g.queue_capacity = pool_.capacity();
  g.workers = pool_.workers();
  g.busy_workers = pool_.busy_workers();
  g.models_loaded = models_.size();
  g.in_flight_requests = in_flight_.load();
  ApiResponse out;
  out.content_type = "text/plain; version=0.0.4; charset=utf-8";
  out.body = metrics_.render(g);
  return out;
}

ApiResponse Gateway::list_models() const { return json_response(200, models_.list_json()); }

ApiResponse Gateway::model(const std::string& name, const std::string& request_id) const {
  const auto model = models_.find(name);
  if (!model)
    return error_response(to_api_error(WishError(ErrorCategory::NotFound, "model_not_found",
                                                 "no model named '" + name + "' is loaded", {{"model", name}})),
                          request_id);
  nlohmann::json info = model_info(*model);
  info["is_default"] = name == models_.default_name();
  return json_response(200, info);
}

ApiResponse Gateway::model_report(const std::string& name, const std::string& request_id) const {
  const auto model = models_.find(name);
  if (!model)
    return error_response(to_api_error(WishError(ErrorCategory::NotFound, "model_not_found",
                                                 "no model named '" + name + "' is loaded", {{"model", name}})),
                          request_id);
  const std::filesystem::path path = training_report_path(*model);
  const auto not_found = [&](const std::string& why) {
    return error_response(to_api_error(WishError(ErrorCategory::NotFound, "report_not_found",
                                                 "model '" + name + "' has no training report: " + why,
                                                 {{"model", name}, {"file", path.filename().string()}})),
                          request_id);
  };
  std::ifstream in(path, std::ios::binary);
  if (!in) return not_found(path.filename().string() + " is not beside the model file");
  nlohmann::json report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!report.is_object()) return not_found(path.filename().string() + " is not a JSON object");
  return json_response(200, report);
}

ApiResponse Gateway::reload() {
  const ReloadReport report = models_.reload();
  metrics_.count_reload(report.ok());
  return json_response(200, report.to_json());
}

std::shared_ptr<const LoadedModel> Gateway::resolve_model(Operation op, const ComputeParams& params) const {
  if (op != Operation::Classify) return nullptr;
  auto model = models_.find(params.model);
  if (model) return model;
  if (!params.model.empty())
    throw WishError(ErrorCategory::NotFound, "model_not_found", "no model named '" + params.model + "' is loaded",
                    {{"model", params.model}});
  if (models_.size() == 0) throw WishError(ErrorCategory::Unavailable, "no_model_loaded", "no classifier model is loaded");
  throw InvalidInputError("model_required", "several models are loaded and none is the default; name one with ?model=");
}

AdmissionVerdict Gateway::admit(const AdmissionQuery& query, const std::string& request_id) {
  AdmissionVerdict verdict;
  ApiError refusal;
  verdict.admission = take_place(query, refusal);
  if (!verdict.admission) verdict.refusal = error_response(refusal, request_id);
  return verdict;
}

std::shared_ptr<Admission> Gateway::take_place(const AdmissionQuery& query, ApiError& refusal) {
  if (grace_over_.load()) {
    metrics_.count_rejected("shutting_down");
    refusal = shutting_down_error();
    return nullptr;
  }
  if (query.content_length && *query.content_length > config_.max_upload_bytes) {
    refusal = to_api_error(WishError(ErrorCategory::TooLarge, "payload_too_large",
                                     "the request body (" + std::to_string(*query.content_length) +
                                         " bytes) exceeds the upload limit of " +
                                         std::to_string(config_.max_upload_bytes) + " bytes",
                                     {{"content_length", static_cast<std::int64_t>(*query.content_length)},
                                      {"limit", static_cast<std::int64_t>(config_.max_upload_bytes)}}));
    return nullptr;
  }
  auto admission = std::make_shared<Admission>();
  admission->place = pool_.try_reserve();
  if (!admission->place) {
    metrics_.count_rejected("queue_full");
    refusal = to_api_error(WishError(ErrorCategory::Unavailable, "queue_full",
                                     "the job queue is full (" + std::to_string(pool_.capacity()) + " waiting, " +
                                         std::to_string(pool_.workers()) + " workers busy); retry later",
                                     {{"queue_capacity", static_cast<std::int64_t>(pool_.capacity())},
                                      {"workers", static_cast<std::int64_t>(pool_.workers())}}));
    return nullptr;
  }
  // By time: the wait the jobs already admitted predict, plus this request's own prediction, against its time limit
  // counted from arrival. A request is never refused for its own size when a worker is free for it at once (it
  // alone past the limit is the time limit's business, not overload's). A label volume is not known to be one
  // before its body is read: it is judged as a mesh of its size here.
  const std::optional<double> own =
      query.content_length ? backlog_->predict(*query.content_length) : std::optional<double>{};
  if (config_.admit_fraction > 0 && own) {
    const double wait = backlog_->wait_seconds();
    const double elapsed = std::chrono::duration<double>(Clock::now() - query.arrival).count();
    const double allowed = config_.admit_fraction * config_.time_limit_seconds;
    const double finish = elapsed + wait + *own;
    if (wait > 0 && finish > allowed) {
      metrics_.count_rejected("queue_time");
      refusal = to_api_error(WishError(
          ErrorCategory::Unavailable, "queue_full",
          fmt::format("the work queued ahead ({:.1f} s predicted) and this request's own ({:.1f} s) would end "
                      "{:.1f} s after its arrival, past {:.1f} s ({:g} of the {:g} s time limit); retry later",
                      wait, *own, finish, allowed, config_.admit_fraction, config_.time_limit_seconds),
          {{"predicted_wait_seconds", wait}, {"predicted_seconds", *own},
           {"time_limit_seconds", config_.time_limit_seconds}, {"admit_fraction", config_.admit_fraction}}));
      // When enough of the work ahead should be done for this request to fit.
      refusal.retry_after_seconds = std::max(refusal.retry_after_seconds,
                                             static_cast<int>(std::ceil(std::min(finish - allowed, wait))));
      return nullptr;
    }
  }
  admission->ticket = backlog_->enter(query.content_length);
  return admission;
}

std::vector<ComputeOutcome> Gateway::run_parts(const ComputeRequest& request, const ComputeParams& params,
                                               const std::shared_ptr<const LoadedModel>& model,
                                               const std::vector<MeshPart>& parts, Admission& admission) {
  // One job per part; all of them are queued or none (a batch is not half-accepted). The time limit counts from
  // the request's arrival, so time spent reading the body and waiting in the queue is part of it; a request that
  // uploads a label volume (many objects, each described) has the volume time limit.
  bool any_volume = false;
  for (const auto& part : parts) any_volume = any_volume || part.volume;
  const double limit_seconds = any_volume ? config_.volume_time_limit_seconds : config_.time_limit_seconds;
  const auto limit = std::chrono::duration<double>(limit_seconds);
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  std::vector<std::future<ComputeOutcome>> futures;
  std::vector<WorkerPool::Job> jobs;
  for (const auto& part : parts) {
    // Its place in the work backlog, predicted from its own bytes now that they are known (a volume: unknown).
    const std::uint64_t bytes = part.bytes->size();
    auto ticket = futures.empty() && admission.ticket ? admission.ticket : backlog_->enter(std::nullopt);
    ticket->set_bytes(part.volume ? std::nullopt : std::optional<std::uint64_t>(bytes));
    auto job = std::make_shared<ComputeJob>();
    job->op = request.op;
    job->params = params;
    job->model = model;
    job->part = part;
    job->request_id = request.request_id;
    job->deadline = Deadline::after(limit - (Clock::now() - request.arrival));
    job->deadline.attach_cancel_flag(cancel);
    job->submitted = Clock::now();
    auto promise = std::make_shared<std::promise<ComputeOutcome>>();
    futures.push_back(promise->get_future());
    // The job holds copies (the configuration outlives the pool; the compute function is copied): a job whose
    // request gave up waiting still runs to its next deadline check after this function returned.
    // A mesh answered 200 teaches the backlog its worker seconds (refusals end early and would teach it wrong).
    jobs.push_back([job, promise, cfg = &config_, compute = compute_, ticket, backlog = backlog_, bytes,
                    learn = !part.volume] {
      ticket->start();
      const auto started = Clock::now();
      ComputeOutcome outcome = compute(*job, *cfg);
      if (learn && outcome.status == 200)
        backlog->learn(bytes, std::chrono::duration<double>(Clock::now() - started).count());
      promise->set_value(std::move(outcome));
    });
  }
  if (!pool_.try_submit(std::move(jobs), admission.place)) {
    metrics_.count_rejected("queue_full");
    throw WishError(ErrorCategory::Unavailable, "queue_full",
                    "the job queue is full (" + std::to_string(pool_.capacity()) + " waiting, " +
                        std::to_string(pool_.workers()) + " workers busy); retry later",
                    {{"queue_capacity", static_cast<std::int64_t>(pool_.capacity())},
                     {"workers", static_cast<std::int64_t>(pool_.workers())}});
  }
  CancelRegistry::Registration registered(cancels_, cancel);
  std::vector<ComputeOutcome> outcomes;
  // The pipeline checks the deadline between steps; the extra second covers the last step before a check.
  const auto wait_until = request.arrival + std::chrono::duration_cast<Clock::duration>(limit) + std::chrono::seconds(1);
  for (auto& f : futures) {
    if (f.wait_until(wait_until) == std::future_status::ready) {
      outcomes.push_back(f.get());
      continue;
    }
    cancel->store(true);  // the job stops at its next check; its result is dropped
    ComputeOutcome late;
    late.error = to_api_error(TimeoutError("time limit of " + std::to_string(limit_seconds) + " s exceeded",
                                           {{"stage", std::string("compute")}, {"limit_seconds", limit_seconds}}));
    late.status = late.error.status;
    outcomes.push_back(std::move(late));
  }
  return outcomes;
}

ApiResponse Gateway::assemble(const ComputeRequest& request, const std::vector<MeshPart>& parts,
                              std::vector<ComputeOutcome>& outcomes) {
  std::int64_t vertices = 0, faces = 0;
  bool counted = false;
  for (const auto& o : outcomes) {
    for (const auto& [stage, seconds] : o.stages) metrics_.observe_stage(stage, seconds);
    if (o.vertices >= 0) { vertices += o.vertices; faces += o.faces; counted = true; }
    if (o.status >= 500 && o.status != 503 && o.status != 504)
      spdlog::error("request {}: {} {}", request.request_id, o.error.code, o.error.message);
  }
  ApiResponse out;
  if (!request.multipart) {
    auto& o = outcomes.front();
    if (o.result.is_null()) {
      out = error_response(o.error, request.request_id);
    } else {
      // A result, or a label volume whose objects did not all succeed (207, or their common 4xx with the first
      // refusal at the top level like every error answer): the VolumeResult still lists every object.
      o.result["request_id"] = request.request_id;
      if (o.status >= 400) o.result["error"] = error_object(o.error);
      out = json_response(o.status, o.result);
      if (o.status != 200) out.error_code = o.error.code;
    }
  } else {
    nlohmann::json results = nlohmann::json::array();
    std::vector<int> statuses;
    const ApiError* first_error = nullptr;   // of the first failed part: the top-level error of a 4xx/5xx answer
    const ApiError* first_refusal = nullptr; // of the first part not 200 (a 207 volume part too): the access line's
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      auto& o = outcomes[i];
      statuses.push_back(o.status);
      nlohmann::json item{{"part", parts[i].field}, {"status", o.status}};
      if (!parts[i].filename.empty()) item["filename"] = parts[i].filename;
      // A label volume part keeps its result (every object) whatever its status; a mesh part has one or the other.
      if (!o.result.is_null()) {
        o.result["request_id"] = request.request_id;
        item["result"] = std::move(o.result);
      }
      if (o.status >= 400) {
        item["error"] = error_object(o.error);
        if (!first_error) first_error = &o.error;
      }
      if (o.status != 200 && !first_refusal) first_refusal = &o.error;
      results.push_back(std::move(item));
    }
    // Every part failed the same way: the answer has that status, and (like every 4xx/5xx answer) a top-level
    // `error`, the first part's, so a client that only reads error.code still finds it.
    const int status = batch_status(statuses);
    nlohmann::json body{{"request_id", request.request_id}, {"results", std::move(results)}};
    if (status >= 400 && first_error) body["error"] = error_object(*first_error);
    out = json_response(status, body);
    if (first_refusal) out.error_code = first_refusal->code;
    if (status == 503 && first_error && first_error->retry_after_seconds > 0)
      out.headers.emplace_back("Retry-After", std::to_string(first_error->retry_after_seconds));
  }
  if (counted) { out.vertices = vertices; out.faces = faces; }
  return out;
}

ApiResponse Gateway::compute(ComputeRequest request) {
  ++in_flight_;
  struct Leave { std::atomic<int>& n; ~Leave() { --n; } } leave{in_flight_};
  int part_count = 0;
  try {
    std::vector<MeshPart> parts;
    if (request.multipart) parts = split_multipart(std::move(request.form), request.params, config_);
    else parts.push_back(raw_body_part(std::move(request.body), request.content_type));
    part_count = static_cast<int>(parts.size());
    for (auto& part : parts) part.volume = detect_volume_format(*part.bytes) != VolumeFormat::Unknown;

    const ComputeParams params = parse_compute_params(request.op, request.params, config_);
    const auto model = resolve_model(request.op, params);
    if (model) check_descriptor_settings(params, *model);
    if (grace_over_.load()) {
      metrics_.count_rejected("shutting_down");
      throw WishError(ErrorCategory::Unavailable, "shutting_down", "the server is shutting down");
    }
    // Admitted from its headers by the transport, or here from the body's size.
    std::shared_ptr<Admission> admission = std::move(request.admission);
    if (!admission) {
      std::uint64_t bytes = 0;
      for (const auto& part : parts) bytes += part.bytes->size();
      ApiError refusal;
      admission = take_place({request.arrival, bytes}, refusal);
      if (!admission) {
        ApiResponse out = error_response(refusal, request.request_id);
        out.parts = part_count;
        return out;
      }
    }
    auto outcomes = run_parts(request, params, model, parts, *admission);
    ApiResponse out = assemble(request, parts, outcomes);
    out.parts = part_count;
    return out;
  } catch (...) {
    const ApiError error = to_api_error(std::current_exception());
    if (error.status >= 500 && error.status != 503)
      spdlog::error("request {}: {} {}", request.request_id, error.code, error.message);
    if (error.status == 504) metrics_.count_rejected("timeout");
    ApiResponse out = error_response(error, request.request_id);
    out.parts = part_count;
    return out;
  }
}

}  // namespace wish::server
