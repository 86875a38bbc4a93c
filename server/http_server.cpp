// The only translation unit that includes httplib.h (see http_server.hpp).
#include "server/http_server.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <random>
#include <set>

#include <spdlog/spdlog.h>

#include "server/compute_service.hpp"
#include "server/error_mapping.hpp"
#include "server/logging.hpp"
#include "server/openapi_document.hpp"
#include "server/request_parsing.hpp"
#include "server/static_assets.hpp"

namespace wish::server {

namespace {

using Clock = std::chrono::steady_clock;

// Per-request bookkeeping for the access line and metrics. httplib runs pre-routing, the handler, the error
// handler and the logger of one request on the same thread, one request at a time, so thread_local is exact.
struct RequestState {
  std::string request_id;
  Clock::time_point start{};
  std::string route = "unmatched";
  std::uint64_t bytes_in = 0;
  std::int64_t vertices = -1, faces = -1;
  int parts = 0;
  std::string error_code;
};
thread_local RequestState t_request;

std::string new_request_id() {
  thread_local std::mt19937_64 rng{std::random_device{}() ^
                                   static_cast<std::uint64_t>(Clock::now().time_since_epoch().count())};
  static constexpr char hex[] = "0123456789abcdef";
  std::string id(16, '0');
  std::uint64_t v = rng();
  for (auto& c : id) { c = hex[v & 15]; v >>= 4; }
  return id;
}

// A client-sent X-Request-Id is reused when it is short and plain (it ends up in logs).
bool acceptable_request_id(const std::string& id) {
  if (id.empty() || id.size() > 128) return false;
  for (unsigned char c : id)
    if (!(std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == ':')) return false;
  return true;
}

bool constant_time_equal(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i % (b.empty() ? 1 : b.size())]);
  return diff == 0;
}

void write_json(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

}  // namespace

struct HttpServer::Impl {
  const ServerConfig& config;
  ModelRegistry& models;
  WorkerPool& pool;
  Metrics& metrics;
  httplib::Server server;
  std::atomic<bool> draining{false};
  std::atomic<int> in_flight{0};
  std::mutex cancel_mutex;
  std::set<std::shared_ptr<std::atomic<bool>>> cancel_flags;  // of in-flight compute requests

  Impl(const ServerConfig& c, ModelRegistry& m, WorkerPool& p, Metrics& me) : config(c), models(m), pool(p), metrics(me) {
    const std::size_t threads = static_cast<std::size_t>(config.http_threads);
    server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    server.set_payload_max_length(config.max_upload_bytes);
    // httplib writes the headers and the body of a response separately; with Nagle's algorithm on, the body waits
    // for the client's delayed ACK (40 ms on Linux): a 5 ms describe of a small mesh took 46 ms end to end.
    server.set_tcp_nodelay(true);
    server.set_keep_alive_timeout(2);
    server.set_read_timeout(30, 0);
    server.set_write_timeout(30, 0);
    install_hooks();
    install_routes();
  }

  void respond_error(httplib::Response& res, const ApiError& error) {
    t_request.error_code = error.code;
    if (error.retry_after_seconds > 0) res.set_header("Retry-After", std::to_string(error.retry_after_seconds));
    if (error.status == 401) res.set_header("WWW-Authenticate", "Bearer");
    write_json(res, error.status, error_body(error, t_request.request_id));
  }

  void install_hooks() {
    server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      t_request = RequestState{};
      t_request.start = Clock::now();
      const std::string incoming = req.get_header_value("X-Request-Id");
      t_request.request_id = acceptable_request_id(incoming) ? incoming : new_request_id();
      res.set_header("X-Request-Id", t_request.request_id);
      if (!config.auth_token.empty() && req.path.rfind("/v1/", 0) == 0) {
        const std::string header = req.get_header_value("Authorization");
        const std::string expected = "Bearer " + config.auth_token;
        if (!constant_time_equal(header, expected)) {
          t_request.route = "auth";
          res.set_header("Connection", "close");  // the body (if any) is not read
          respond_error(res, unauthorized_error());
          return httplib::Server::HandlerResponse::Handled;
        }
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });

    // Every >= 400 response passes here; a response without a body came from httplib itself (404 route, 413
    // payload, 400 framing): give it the one error body.
    server.set_error_handler(httplib::Server::HandlerWithResponse(
        [this](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (t_request.request_id.empty()) t_request.request_id = new_request_id();
      res.set_header("X-Request-Id", t_request.request_id);
      ApiError error = res.status == 404 ? route_not_found_error(req.method, req.path) : status_error(res.status);
      respond_error(res, error);
      return httplib::Server::HandlerResponse::Handled;
    }));

    server.set_exception_handler([this](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
      const ApiError error = to_api_error(ep);
      if (error.status >= 500) spdlog::error("request {}: unhandled exception: {}", t_request.request_id, error.message);
      respond_error(res, error);
    });

    server.set_logger([this](const httplib::Request& req, const httplib::Response& res) {
      const double seconds = t_request.start == Clock::time_point{}
                                 ? 0.0
                                 : std::chrono::duration<double>(Clock::now() - t_request.start).count();
      metrics.observe_request(t_request.route, res.status, seconds);
      AccessRecord r;
      r.request_id = t_request.request_id.empty() ? res.get_header_value("X-Request-Id") : t_request.request_id;
      r.method = req.method;
      r.path = req.path;
      r.route = t_request.route;
      r.status = res.status;
      r.bytes_in = t_request.bytes_in ? t_request.bytes_in : req.body.size();
      r.bytes_out = res.body.size();
      r.vertices = t_request.vertices;
      r.faces = t_request.faces;
      r.parts = t_request.parts;
      r.seconds = seconds;
      r.error_code = t_request.error_code;
      log_access(r);
      t_request = RequestState{};
    });
  }

  void install_routes() {
    server.Get("/healthz", [this](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/healthz";
      write_json(res, 200, {{"status", "ok"}});
    });

    server.Get("/readyz", [this](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/readyz";
      const std::size_t n = models.size();
      const bool accepting = pool.accepting();
      const bool is_draining = draining.load();
      if (n > 0 && accepting && !is_draining) {
        write_json(res, 200, {{"ready", true}, {"models", n}, {"queue_depth", pool.queue_depth()},
                              {"queue_capacity", pool.capacity()}, {"workers", pool.workers()}});
        return;
      }
      std::string reason = is_draining ? "shutting down" : n == 0 ? "no model loaded" : "the job queue is full";
      respond_error(res, to_api_error(WishError(ErrorCategory::Unavailable, "not_ready", "not ready: " + reason,
                                                {{"models", static_cast<std::int64_t>(n)},
                                                 {"queue_depth", static_cast<std::int64_t>(pool.queue_depth())},
                                                 {"shutting_down", std::string(is_draining ? "true" : "false")}})));
    });

    server.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/metrics";
      Gauges g;
      g.queue_depth = pool.queue_depth();
      g.queue_capacity = pool.capacity();
      g.workers = pool.workers();
      g.busy_workers = pool.busy_workers();
      g.models_loaded = models.size();
      g.in_flight_requests = in_flight.load();
      res.set_content(metrics.render(g), "text/plain; version=0.0.4; charset=utf-8");
    });

    server.Get("/openapi.json", [](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/openapi.json";
      const auto doc = openapi_document();
      res.set_content(doc.data(), doc.size(), "application/json");
    });

    server.Get("/v1/models", [this](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/v1/models";
      write_json(res, 200, models.list_json());
    });

    server.Get(R"(/v1/models/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
      t_request.route = "/v1/models/{name}";
      const std::string name = req.matches[1];
      const auto model = models.find(name);
      if (!model) {
        respond_error(res, to_api_error(WishError(ErrorCategory::NotFound, "model_not_found",
                                                  "no model named '" + name + "' is loaded", {{"model", name}})));
        return;
      }
      nlohmann::json info = model_info(*model);
      info["is_default"] = name == models.default_name();
      write_json(res, 200, info);
    });

    server.Post("/v1/admin/reload", [this](const httplib::Request&, httplib::Response& res) {
      t_request.route = "/v1/admin/reload";
      const ReloadReport report = models.reload();
      metrics.count_reload(report.ok());
      write_json(res, 200, report.to_json());
    });

    server.Post("/v1/describe", [this](const httplib::Request& req, httplib::Response& res,
                                       const httplib::ContentReader& reader) {
      t_request.route = "/v1/describe";
      handle_compute(Operation::Describe, req, res, reader);
    });
    server.Post("/v1/classify", [this](const httplib::Request& req, httplib::Response& res,
                                       const httplib::ContentReader& reader) {
      t_request.route = "/v1/classify";
      handle_compute(Operation::Classify, req, res, reader);
    });

    // Last: the web page's files (static_assets.hpp) for every other GET; a miss stays a bodiless 404, which the
    // error handler turns into the usual error body.
    if (!config.web_dir.empty()) {
      server.Get(R"(/.*)", [this](const httplib::Request& req, httplib::Response& res) {
        t_request.route = "/ (web page)";
        StaticAsset asset = load_static_asset(config.web_dir, req.path);
        if (asset.status != 200) {
          res.status = asset.status;
          return;
        }
        res.set_header("Cache-Control", asset.cache_control);
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_content(std::move(asset.body), asset.content_type);
      });
    }
  }

  // Reading the body ourselves (content reader) rather than letting httplib do it: a raw body sent with curl's
  // default form-urlencoded type is not parsed (and capped at 8 KB) by httplib, and multipart parts stream in.
  static void throw_read_failure(int status) {
    if (status == 413) throw WishError(ErrorCategory::TooLarge, "payload_too_large", "the request body exceeds the upload limit");
    throw InvalidInputError("bad_request", "the request body could not be read (framing or multipart syntax)");
  }

  void handle_compute(Operation op, const httplib::Request& req, httplib::Response& res,
                      const httplib::ContentReader& reader) {
    ++in_flight;
    struct Leave { std::atomic<int>& n; ~Leave() { --n; } } leave{in_flight};
    try {
      ParamMap params(req.params.begin(), req.params.end());
      std::vector<MeshPart> parts;
      const bool multipart = req.is_multipart_form_data();
      if (multipart) {
        std::vector<FormPart> form;
        std::size_t total = 0;
        const bool ok = reader(
            [&](const httplib::MultipartFormData& file) {
              form.push_back({file.name, file.filename, file.content_type, {}});
              return form.size() <= static_cast<std::size_t>(config.max_parts) + 64;  // parts + parameter fields
            },
            [&](const char* data, std::size_t n) {
              total += n;
              form.back().content.append(data, n);
              return true;
            });
        t_request.bytes_in = total;
        if (!ok) {
          if (res.status != 413 && form.size() > static_cast<std::size_t>(config.max_parts) + 64)
            throw WishError(ErrorCategory::TooLarge, "too_many_parts", "too many parts in one multipart request");
          throw_read_failure(res.status);
        }
        parts = split_multipart(std::move(form), params, config);
      } else {
        std::string body;
        const bool ok = reader([&](const char* data, std::size_t n) {
          body.append(data, n);
          return true;
        });
        t_request.bytes_in = body.size();
        if (!ok) throw_read_failure(res.status);
        parts.push_back(raw_body_part(std::move(body), req.get_header_value("Content-Type")));
      }
      res.status = -1;  // the content reader may have set an error status; the outcome decides
      t_request.parts = static_cast<int>(parts.size());

      const ComputeParams cp = parse_compute_params(op, params, config);
      std::shared_ptr<const LoadedModel> model;
      if (op == Operation::Classify) {
        model = models.find(cp.model);
        if (!model) {
          if (!cp.model.empty())
            throw WishError(ErrorCategory::NotFound, "model_not_found", "no model named '" + cp.model + "' is loaded",
                            {{"model", cp.model}});
          if (models.size() == 0)
            throw WishError(ErrorCategory::Unavailable, "no_model_loaded", "no classifier model is loaded");
          throw InvalidInputError("model_required", "several models are loaded and none is the default; name one with ?model=");
        }
        check_descriptor_settings(cp, *model);
      }
      if (draining.load()) {
        metrics.count_rejected("shutting_down");
        throw WishError(ErrorCategory::Unavailable, "shutting_down", "the server is shutting down");
      }

      // One job per mesh; all of them are queued or none (a batch is not half-accepted).
      const auto arrival = t_request.start;
      const auto limit = std::chrono::duration<double>(config.time_limit_seconds);
      auto cancel = std::make_shared<std::atomic<bool>>(false);
      std::vector<std::future<ComputeOutcome>> futures;
      std::vector<WorkerPool::Job> jobs;
      for (auto& part : parts) {
        auto job = std::make_shared<ComputeJob>();
        job->op = op;
        job->params = cp;
        job->model = model;
        job->part = part;
        job->deadline = Deadline::after(limit - (Clock::now() - arrival));
        job->deadline.attach_cancel_flag(cancel);
        job->submitted = Clock::now();
        auto promise = std::make_shared<std::promise<ComputeOutcome>>();
        futures.push_back(promise->get_future());
        const ServerConfig* cfg = &config;
        jobs.push_back([job, promise, cfg] { promise->set_value(run_compute(*job, *cfg)); });
      }
      if (!pool.try_submit(std::move(jobs))) {
        metrics.count_rejected("queue_full");
        throw WishError(ErrorCategory::Unavailable, "queue_full",
                        "the job queue is full (" + std::to_string(pool.capacity()) + " waiting, " +
                            std::to_string(pool.workers()) + " workers busy); retry later",
                        {{"queue_capacity", static_cast<std::int64_t>(pool.capacity())},
                         {"workers", static_cast<std::int64_t>(pool.workers())}});
      }
      {
        std::lock_guard lock(cancel_mutex);
        cancel_flags.insert(cancel);
      }
      std::vector<ComputeOutcome> outcomes;
      // The pipeline checks the deadline between steps; the extra second covers the last step before a check.
      const auto wait_until = arrival + std::chrono::duration_cast<Clock::duration>(limit) + std::chrono::seconds(1);
      for (auto& f : futures) {
        if (f.wait_until(wait_until) == std::future_status::ready) {
          outcomes.push_back(f.get());
          continue;
        }
        cancel->store(true);  // the job stops at its next check; its result is dropped
        ComputeOutcome late;
        late.error = to_api_error(TimeoutError("time limit of " + std::to_string(config.time_limit_seconds) +
                                               " s exceeded", {{"stage", std::string("compute")}}));
        late.status = late.error.status;
        outcomes.push_back(std::move(late));
      }
      {
        std::lock_guard lock(cancel_mutex);
        cancel_flags.erase(cancel);
      }
      respond_outcomes(multipart, parts, outcomes, res);
    } catch (...) {
      const ApiError error = to_api_error(std::current_exception());
      if (error.status >= 500 && error.status != 503)
        spdlog::error("request {}: {} {}", t_request.request_id, error.code, error.message);
      if (error.status == 504) metrics.count_rejected("timeout");
      respond_error(res, error);
    }
  }

  void respond_outcomes(bool multipart, const std::vector<MeshPart>& parts, std::vector<ComputeOutcome>& outcomes,
                        httplib::Response& res) {
    std::int64_t vertices = 0, faces = 0;
    bool counted = false;
    for (const auto& o : outcomes) {
      for (const auto& [stage, seconds] : o.stages) metrics.observe_stage(stage, seconds);
      if (o.vertices >= 0) { vertices += o.vertices; faces += o.faces; counted = true; }
      if (o.status >= 500 && o.status != 503 && o.status != 504)
        spdlog::error("request {}: {} {}", t_request.request_id, o.error.code, o.error.message);
    }
    if (counted) { t_request.vertices = vertices; t_request.faces = faces; }

    if (!multipart) {
      auto& o = outcomes.front();
      if (o.status != 200) {
        respond_error(res, o.error);
        return;
      }
      o.result["request_id"] = t_request.request_id;
      write_json(res, 200, o.result);
      return;
    }
    nlohmann::json results = nlohmann::json::array();
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      auto& o = outcomes[i];
      nlohmann::json item{{"part", parts[i].field}, {"status", o.status}};
      if (!parts[i].filename.empty()) item["filename"] = parts[i].filename;
      if (o.status == 200) {
        o.result["request_id"] = t_request.request_id;
        item["result"] = std::move(o.result);
      } else {
        item["error"] = error_object(o.error);
        if (t_request.error_code.empty()) t_request.error_code = o.error.code;
      }
      results.push_back(std::move(item));
    }
    write_json(res, 200, {{"request_id", t_request.request_id}, {"results", std::move(results)}});
  }
};

HttpServer::HttpServer(const ServerConfig& config, ModelRegistry& models, WorkerPool& pool, Metrics& metrics)
    : impl_(std::make_unique<Impl>(config, models, pool, metrics)) {}

HttpServer::~HttpServer() = default;

int HttpServer::bind() {
  const auto& c = impl_->config;
  if (c.port == 0) {
    const int port = impl_->server.bind_to_any_port(c.host);
    if (port <= 0) throw std::runtime_error("cannot bind to " + c.host + " (any port)");
    return port;
  }
  if (!impl_->server.bind_to_port(c.host, c.port))
    throw std::runtime_error("cannot bind to " + c.host + ":" + std::to_string(c.port) + " (in use or not permitted)");
  return c.port;
}

void HttpServer::serve() { impl_->server.listen_after_bind(); }

void HttpServer::begin_drain() { impl_->draining = true; }

void HttpServer::stop() { impl_->server.stop(); }

void HttpServer::cancel_in_flight() {
  std::lock_guard lock(impl_->cancel_mutex);
  for (const auto& flag : impl_->cancel_flags) flag->store(true);
}

int HttpServer::in_flight() const { return impl_->in_flight.load(); }

}  // namespace wish::server
