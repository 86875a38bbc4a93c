// The transport: the only translation unit that includes httplib.h (see http_server.hpp). It reads an httplib
// request into the gateway's neutral values (gateway.hpp), writes the gateway's ApiResponse to the wire, and keeps
// what is HTTP's own: request ids, bearer auth, httplib's bare error statuses, the access line.
#include "server/http_server.hpp"

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <random>
#include <type_traits>

#include <spdlog/spdlog.h>

#include "server/api_response.hpp"
#include "server/cancel_registry.hpp"
#include "server/connection_threads.hpp"
#include "server/error_mapping.hpp"
#include "server/gateway.hpp"
#include "server/logging.hpp"
#include "server/openapi_document.hpp"
#include "server/request_parsing.hpp"
#include "server/routes.hpp"
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

// The one place a neutral response reaches the wire; what the access line needs is kept in t_request.
void write_response(httplib::Response& res, const ApiResponse& response) {
  res.status = response.status;
  for (const auto& [name, value] : response.headers) res.set_header(name, value);
  res.set_content(response.body, response.content_type);
  if (!response.error_code.empty() && t_request.error_code.empty()) t_request.error_code = response.error_code;
  if (response.parts > 0) t_request.parts = response.parts;
  if (response.vertices >= 0) { t_request.vertices = response.vertices; t_request.faces = response.faces; }
}

void write_error(httplib::Response& res, const ApiError& error) {
  write_response(res, error_response(error, t_request.request_id));
}

// Reading the body ourselves (content reader) rather than letting httplib do it: a raw body sent with curl's
// default form-urlencoded type is not parsed (and capped at 8 KB) by httplib, and multipart parts stream in.
[[noreturn]] void throw_read_failure(int status) {
  if (status == 413) throw WishError(ErrorCategory::TooLarge, "payload_too_large", "the request body exceeds the upload limit");
  throw InvalidInputError("bad_request", "the request body could not be read (framing or multipart syntax)");
}

// httplib request -> the gateway's neutral ComputeRequest. Throws WishError for a body that cannot be read.
ComputeRequest read_compute_request(Operation op, const httplib::Request& req, httplib::Response& res,
                                    const httplib::ContentReader& reader, int max_parts) {
  ComputeRequest out;
  out.op = op;
  out.request_id = t_request.request_id;
  out.arrival = t_request.start;
  out.params = ParamMap(req.params.begin(), req.params.end());
  out.multipart = req.is_multipart_form_data();
  if (out.multipart) {
    const std::size_t cap = static_cast<std::size_t>(max_parts) + 64;  // parts + parameter fields
    std::size_t total = 0;
    const bool ok = reader(
        [&](const httplib::MultipartFormData& file) {
          out.form.push_back({file.name, file.filename, file.content_type, {}});
          return out.form.size() <= cap;
        },
        [&](const char* data, std::size_t n) {
          total += n;
          out.form.back().content.append(data, n);
          return true;
        });
    t_request.bytes_in = total;
    if (!ok) {
      if (res.status != 413 && out.form.size() > cap)
        throw WishError(ErrorCategory::TooLarge, "too_many_parts", "too many parts in one multipart request");
      throw_read_failure(res.status);
    }
  } else {
    const bool ok = reader([&](const char* data, std::size_t n) {
      out.body.append(data, n);
      return true;
    });
    t_request.bytes_in = out.body.size();
    if (!ok) throw_read_failure(res.status);
    out.content_type = req.get_header_value("Content-Type");
  }
  res.status = -1;  // the content reader may have set an error status; the outcome decides
  return out;
}

// The time of the last accepted connection or request start, for the quiet period before a stop (run_server.cpp).
class ActivityClock {
 public:
  void touch() { last_.store(Clock::now().time_since_epoch().count(), std::memory_order_relaxed); }
  double seconds_since() const {
    return std::chrono::duration<double>(Clock::now() - Clock::time_point(Clock::duration(last_.load()))).count();
  }

 private:
  std::atomic<Clock::rep> last_{Clock::now().time_since_epoch().count()};
};

// httplib's task queue over the on-demand connection threads (connection_threads.hpp); an accepted connection is
// activity (its request may still be on the way).
class ConnectionTaskQueue : public httplib::TaskQueue {
 public:
  ConnectionTaskQueue(std::size_t warm_threads, std::size_t max_threads, ActivityClock& activity)
      : threads_(warm_threads, max_threads), activity_(activity) {}
  void enqueue(std::function<void()> fn) override {
    activity_.touch();
    threads_.enqueue(std::move(fn));
  }
  void shutdown() override { threads_.shutdown(); }

 private:
  ConnectionThreads threads_;
  ActivityClock& activity_;
};

}  // namespace

struct HttpServer::Impl {
  const ServerConfig& config;
  Metrics& metrics;
  CancelRegistry cancels;
  Gateway gateway;
  ActivityClock activity;
  httplib::Server server;

  Impl(const ServerConfig& c, ModelRegistry& m, WorkerPool& p, Metrics& me)
      : config(c), metrics(me), gateway(c, m, p, me, cancels) {
    const std::size_t threads = static_cast<std::size_t>(config.http_threads);
    // Warm: every worker busy and the job queue full still finds a thread (so it is answered 503 at once).
    const std::size_t warm = static_cast<std::size_t>(config.workers + config.queue_size + 8);
    server.new_task_queue = [this, warm, threads] { return new ConnectionTaskQueue(warm, threads, activity); };
    server.set_payload_max_length(config.max_upload_bytes);
    // httplib writes the headers and the body of a response separately; with Nagle's algorithm on, the body waits
    // for the client's delayed ACK (40 ms on Linux): a 5 ms describe of a small mesh took 46 ms end to end.
    server.set_tcp_nodelay(true);
    server.set_keep_alive_timeout(2);
    // Per read: a silent client is dropped after this, a slow one that keeps sending is not.
    const auto read_timeout = std::chrono::duration<double>(config.read_timeout_seconds);
    const auto read_sec = std::chrono::duration_cast<std::chrono::seconds>(read_timeout);
    server.set_read_timeout(read_sec.count(),
                            std::chrono::duration_cast<std::chrono::microseconds>(read_timeout - read_sec).count());
    server.set_write_timeout(30, 0);
    install_hooks();
    install_routes();
  }

  void install_hooks() {
    server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      activity.touch();  // a request on a kept-alive connection is activity too
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
          write_error(res, unauthorized_error());
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
      ApiError error = status_error(res.status);
      if (res.status == 404) {
        // A known path with another method is 405 with Allow (httplib itself answers 404 for it).
        const std::string allow = allowed_methods(req.path, !config.web_dir.empty());
        if (!allow.empty() && !method_allowed(allow, req.method)) {
          error = method_not_allowed_error(req.method, req.path, allow);
          res.set_header("Allow", allow);
        } else {
          error = route_not_found_error(req.method, req.path);
        }
      }
      write_error(res, error);
      return httplib::Server::HandlerResponse::Handled;
    }));

    server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
      const ApiError error = to_api_error(ep);
      if (error.status >= 500) spdlog::error("request {}: unhandled exception: {}", t_request.request_id, error.message);
      write_error(res, error);
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

  // Registers `handler` for the route `id` (routes.hpp) by its method and path, naming it in the access log.
  template <class Handler> void add_route(RouteId id, Handler handler) {
    const Route& r = route(id);
    const std::string pattern = http_pattern(r);
    if constexpr (std::is_invocable_v<Handler, const httplib::Request&, httplib::Response&,
                                      const httplib::ContentReader&>) {
      server.Post(pattern, [&r, handler](const httplib::Request& req, httplib::Response& res,
                                         const httplib::ContentReader& reader) {
        t_request.route = r.path;
        handler(req, res, reader);
      });
    } else if (method_allowed(r.allow, "GET")) {
      server.Get(pattern, [&r, handler](const httplib::Request& req, httplib::Response& res) {
        t_request.route = r.path;
        handler(req, res);
      });
    } else {
      server.Post(pattern, [&r, handler](const httplib::Request& req, httplib::Response& res) {
        t_request.route = r.path;
        handler(req, res);
      });
    }
  }

  void install_routes() {
    using Req = httplib::Request;
    using Res = httplib::Response;
    add_route(RouteId::Healthz, [this](const Req&, Res& res) { write_response(res, gateway.health()); });
    add_route(RouteId::Readyz,
              [this](const Req&, Res& res) { write_response(res, gateway.ready(t_request.request_id)); });
    add_route(RouteId::Metrics, [this](const Req&, Res& res) { write_response(res, gateway.metrics_text()); });
    add_route(RouteId::OpenApi, [](const Req&, Res& res) {
      const auto doc = openapi_document();
      res.set_content(doc.data(), doc.size(), "application/json");
    });
    add_route(RouteId::Models, [this](const Req&, Res& res) { write_response(res, gateway.list_models()); });
    add_route(RouteId::Model, [this](const Req& req, Res& res) {
      write_response(res, gateway.model(req.matches[1], t_request.request_id));
    });
    add_route(RouteId::ModelReport, [this](const Req& req, Res& res) {
      write_response(res, gateway.model_report(req.matches[1], t_request.request_id));
    });
    add_route(RouteId::AdminReload, [this](const Req&, Res& res) { write_response(res, gateway.reload()); });
    add_route(RouteId::Describe, [this](const Req& req, Res& res, const httplib::ContentReader& reader) {
      handle_compute(Operation::Describe, req, res, reader);
    });
    add_route(RouteId::Classify, [this](const Req& req, Res& res, const httplib::ContentReader& reader) {
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

  void handle_compute(Operation op, const httplib::Request& req, httplib::Response& res,
                      const httplib::ContentReader& reader) {
    ComputeRequest request;
    try {
      request = read_compute_request(op, req, res, reader, config.max_parts);
    } catch (...) {
      write_error(res, to_api_error(std::current_exception()));
      return;
    }
    write_response(res, gateway.compute(std::move(request)));
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

void HttpServer::begin_drain() { impl_->gateway.begin_drain(); }

void HttpServer::stop() { impl_->server.stop(); }

void HttpServer::cancel_in_flight() { impl_->cancels.cancel_all(); }

int HttpServer::in_flight() const { return impl_->gateway.in_flight(); }

double HttpServer::seconds_since_activity() const { return impl_->activity.seconds_since(); }

}  // namespace wish::server
