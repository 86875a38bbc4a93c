// The transport: the only translation unit that includes httplib.h (see http_server.hpp). It reads an httplib
// request into the gateway's neutral values (gateway.hpp), writes the gateway's ApiResponse to the wire, and keeps
// what is HTTP's own: request ids, bearer auth, httplib's bare error statuses, the access line, and the connections
// themselves (accepted by listener.hpp, served by Transport below) so that a shutdown answers every request sent.
#include "server/http_server.hpp"

#include <httplib.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <type_traits>

#include <spdlog/spdlog.h>

#include "server/api_response.hpp"
#include "server/cancel_registry.hpp"
#include "server/connection_threads.hpp"
#include "server/error_mapping.hpp"
#include "server/gateway.hpp"
#include "server/listener.hpp"
#include "server/logging.hpp"
#include "server/openapi_document.hpp"
#include "server/request_parsing.hpp"
#include "server/routes.hpp"
#include "server/static_assets.hpp"
#include "server/wake_latch.hpp"

namespace wish::server {

namespace {

using Clock = std::chrono::steady_clock;

// Per-request bookkeeping for the access line and metrics. httplib runs the expect-100 hook, pre-routing, the
// handler, the error handler and the logger of one request on the same thread, one request at a time, so
// thread_local is exact (Transport::serve_connection clears it before each request).
struct RequestState {
  bool begun = false;  // begin_request ran (the expect-100 hook runs before pre-routing)
  std::shared_ptr<Admission> admission;  // a compute request admitted from its headers (the expect-100 hook)
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

// The request's id and start time, once per request (from the expect-100 hook or from pre-routing).
void begin_request(const httplib::Request& req, httplib::Response& res) {
  if (t_request.begun) return;
  t_request.begun = true;
  t_request.start = Clock::now();
  const std::string incoming = req.get_header_value("X-Request-Id");
  t_request.request_id = acceptable_request_id(incoming) ? incoming : new_request_id();
  res.set_header("X-Request-Id", t_request.request_id);
}

bool is_compute_route(const httplib::Request& req) {
  return req.method == "POST" && (req.path == route(RouteId::Describe).path || req.path == route(RouteId::Classify).path);
}

// What the gateway judges a compute request by before its body is read. A chunked body has no length here.
AdmissionQuery admission_query(const httplib::Request& req) {
  AdmissionQuery query;
  query.arrival = t_request.start;
  const std::string length = req.get_header_value("Content-Length");
  std::uint64_t n = 0;
  const auto [end, ec] = std::from_chars(length.data(), length.data() + length.size(), n);
  if (!length.empty() && ec == std::errc() && end == length.data() + length.size()) query.content_length = n;
  return query;
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

// One accepted connection as httplib's request code reads and writes it. httplib's own socket stream is internal to
// the library, so this is the same thing (a small read buffer, poll() before every read and write, the timeouts)
// with one addition: a read waiting for bytes also watches `interrupt` (the end of the shutdown grace period), and
// is then cut short as if the client had stopped sending, so the request is answered 503 at once.
class ConnectionStream final : public httplib::Stream {
 public:
  ConnectionStream(int sock, int read_timeout_ms, int write_timeout_ms, const WakeLatch& interrupt)
      : sock_(sock), read_timeout_ms_(read_timeout_ms), write_timeout_ms_(write_timeout_ms), interrupt_(interrupt) {}

  bool is_readable() const override { return off_ < len_ || wait_readable(); }
  // Unlike httplib's stream, a client that shut down its sending side after its request (EOF pending) is still
  // answered: it can read. A client that is gone makes send() fail.
  bool is_writable() const override { return wait_socket(POLLOUT, write_timeout_ms_); }

  ssize_t read(char* ptr, std::size_t size) override {
    if (off_ == len_) {
      off_ = len_ = 0;
      // Interrupted: 0 (the client "stopped sending"), so a half-read request line or header block still reaches
      // httplib's 400 path and is answered rather than dropped without a word.
      if (!wait_readable()) return interrupted_ ? 0 : -1;
      if (size >= buffer_.size()) return receive(ptr, size);
      const ssize_t n = receive(buffer_.data(), buffer_.size());
      if (n <= 0) return n;
      len_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min(size, len_ - off_);
    std::memcpy(ptr, buffer_.data() + off_, n);
    off_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, std::size_t size) override {
    if (!is_writable()) return -1;
    for (;;) {
      const ssize_t n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      return n;
    }
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { address(::getpeername, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { address(::getsockname, ip, port); }
  int socket() const override { return sock_; }

  bool interrupted() const { return interrupted_; }

 private:
  ssize_t receive(char* ptr, std::size_t size) const {
    for (;;) {
      const ssize_t n = ::recv(sock_, ptr, size, 0);
      if (n < 0 && errno == EINTR) continue;
      return n;
    }
  }

  // Bytes to read within the read timeout (a closed or failed socket counts: recv reports it); false on timeout,
  // and when the grace period ends first (interrupted_).
  bool wait_readable() const {
    pollfd fds[2] = {{sock_, POLLIN, 0}, {interrupt_.fd(), POLLIN, 0}};
    for (;;) {
      const int n = ::poll(fds, 2, read_timeout_ms_);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      if (fds[0].revents != 0) return true;
      interrupted_ = true;
      return false;
    }
  }

  bool wait_socket(short events, int timeout_ms) const {
    pollfd fd{sock_, events, 0};
    for (;;) {
      const int n = ::poll(&fd, 1, timeout_ms);
      if (n < 0 && errno == EINTR) continue;
      return n > 0 && (fd.revents & events) != 0;
    }
  }

  template <class Query>
  void address(Query query, std::string& ip, int& port) const {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    if (query(sock_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) return;
    char host[NI_MAXHOST], service[NI_MAXSERV];
    if (::getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, service, sizeof service,
                      NI_NUMERICHOST | NI_NUMERICSERV) != 0)
      return;
    ip = host;
    port = std::atoi(service);
  }

  int sock_;
  int read_timeout_ms_, write_timeout_ms_;
  const WakeLatch& interrupt_;
  std::array<char, 4096> buffer_{};
  std::size_t off_ = 0, len_ = 0;
  mutable bool interrupted_ = false;
};

// The shutdown phases every connection watches (http_server.hpp): `closing` from the signal on (no new
// connections; an idle kept-alive connection closes; every response says Connection: close), `grace_over` once the
// grace period has run out (reads and silent connections are cut short; what is left is answered 503).
struct ShutdownPhases {
  WakeLatch closing;
  WakeLatch grace_over;
};

// httplib parses, routes and writes each request; the connection around it is ours. httplib's own loop (its
// listen loop and per-connection keep-alive loop) stops reading every connection the moment the server stops:
// one accepted but not yet read, and a kept-alive one whose next request has already arrived, are closed
// unanswered. Here the listener (listener.hpp) takes connections and this loop serves each one: process_request
// is httplib's (protected) request step, called once per request as httplib's loop does.
class Transport : public httplib::Server {
 public:
  int listening_socket() const { return svr_sock_; }

  void serve_connection(int sock, const ShutdownPhases& phases) {
    const int read_ms = static_cast<int>(read_timeout_sec_ * 1000 + read_timeout_usec_ / 1000);
    const int write_ms = static_cast<int>(write_timeout_sec_ * 1000 + write_timeout_usec_ / 1000);
    // As httplib's listen loop does: a blocked send() (window full after poll said writable) is bounded too.
    const timeval send_limit{static_cast<time_t>(write_timeout_sec_), static_cast<suseconds_t>(write_timeout_usec_)};
    ::setsockopt(sock, SOL_SOCKET, SO_SNDTIMEO, &send_limit, sizeof send_limit);
    ConnectionStream stream(sock, read_ms, write_ms, phases.grace_over);
    t_body_unread = false;
    for (std::size_t served = 0; served < keep_alive_max_count_; ++served) {
      if (!next_request_arrives(sock, served == 0, phases)) break;
      const bool last = served + 1 == keep_alive_max_count_ || phases.closing.is_set();
      bool client_closes = false;
      t_response_closes = false;
      t_request = RequestState{};
      if (!process_request(stream, last, client_closes, nullptr) || client_closes || last || t_response_closes ||
          t_body_unread)
        break;
    }
    t_request = RequestState{};  // frees an admission a request that was not answered may have left
    close_connection(sock, stream.interrupted(), t_body_unread);
  }

  // Set by the post-routing hook when the response just written said Connection: close.
  static thread_local bool t_response_closes;
  // Set by a handler that answered without reading the request's body (a refusal from the headers): the
  // connection then closes, lingering for the body (close_connection).
  static thread_local bool t_body_unread;

 private:
  // httplib's keep_alive(): wait up to the keep-alive timeout for the first byte of the next request. Shutting down,
  // a connection that has served a request and has no byte waiting is idle: closed now (its client was not sending).
  // One that has served none keeps its usual wait (its client connected before the listener closed; the request is
  // on its way) unless the grace period ends first. Bytes already there win: that request is answered.
  bool next_request_arrives(int sock, bool fresh, const ShutdownPhases& phases) const {
    pollfd fds[2] = {{sock, POLLIN, 0}, {(fresh ? phases.grace_over : phases.closing).fd(), POLLIN, 0}};
    const auto deadline = Clock::now() + std::chrono::seconds(keep_alive_timeout_sec_);
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      const int n = ::poll(fds, 2, static_cast<int>(std::max<long long>(0, left)));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      return fds[0].revents != 0;
    }
  }

  // A request answered before its body was read (cut short at the end of the grace period, refused by auth, by
  // size or by admission) leaves bytes unread: closing then makes the kernel send a reset, which can destroy the
  // answer before the client reads it. So the write side is shut first (the client sees the answer end) and what
  // the client still sends is read and dropped, never kept, for a bounded time. A refusal from the headers
  // (body_unread) lingers longer, as most clients send the whole body before they read the answer: until the client
  // closes or stops sending for 1 s, at most 30 s (nginx's lingering close does the same).
  static void close_connection(int sock, bool interrupted, bool body_unread) {
    pollfd pending{sock, POLLIN, 0};
    if (interrupted || body_unread || ::poll(&pending, 1, 0) > 0) {
      ::shutdown(sock, SHUT_WR);
      const auto until = Clock::now() + std::chrono::seconds(body_unread ? 30 : 2);
      const int quiet_ms = body_unread ? 1000 : 200;
      std::array<char, 65536> sink;
      pollfd fd{sock, POLLIN, 0};
      while (Clock::now() < until && ::poll(&fd, 1, quiet_ms) > 0 && ::recv(sock, sink.data(), sink.size(), 0) > 0) {
      }
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }
};

thread_local bool Transport::t_response_closes = false;
thread_local bool Transport::t_body_unread = false;

}  // namespace

struct HttpServer::Impl {
  const ServerConfig& config;
  Metrics& metrics;
  CancelRegistry cancels;
  Gateway gateway;
  Transport server;
  ShutdownPhases phases;
  // Warm: every worker busy and the job queue full still finds a thread (so it is answered 503 at once).
  ConnectionThreads connections;
  std::atomic<int> open_connections{0};
  std::unique_ptr<Listener> listener;  // from bind()

  Impl(const ServerConfig& c, ModelRegistry& m, WorkerPool& p, Metrics& me)
      : config(c), metrics(me), gateway(c, m, p, me, cancels),
        connections(static_cast<std::size_t>(c.workers + c.queue_size + 8), static_cast<std::size_t>(c.http_threads)) {
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
      begin_request(req, res);
      if (refuse_unauthorized(req, res)) return httplib::Server::HandlerResponse::Handled;
      return httplib::Server::HandlerResponse::Unhandled;
    });

    // A client that asks before sending its body (Expect: 100-continue; curl does for a body over 1 MB) is answered
    // from the headers: refused (401, 413, 503 + Retry-After) without the body ever being sent, or admitted (its
    // queue place held, t_request.admission) and told to send it.
    server.set_expect_100_continue_handler([this](const httplib::Request& req, httplib::Response& res) {
      begin_request(req, res);
      if (refuse_unauthorized(req, res)) return res.status;
      if (is_compute_route(req)) {
        t_request.route = req.path;
        if (!admit_from_headers(req, res)) return res.status;
      }
      return 100;
    });

    // Runs as each response's headers are written. From the signal on, every response closes its connection, so a
    // kept-alive client sends its next request elsewhere instead of racing the close of an idle connection.
    server.set_post_routing_handler([this](const httplib::Request&, httplib::Response& res) {
      if (phases.closing.is_set() && res.get_header_value("Connection") != "close")
        res.set_header("Connection", "close");
      Transport::t_response_closes = res.get_header_value("Connection") == "close";
    });

    // Every >= 400 response passes here; a response without a body came from httplib itself (404 route, 413
    // payload, 400 framing): give it the one error body.
    server.set_error_handler(httplib::Server::HandlerWithResponse(
        [this](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (t_request.request_id.empty()) t_request.request_id = new_request_id();
      res.set_header("X-Request-Id", t_request.request_id);
      ApiError error = status_error(res.status);
      // httplib's 400 for a request line or headers cut short by the end of the grace period: not the client's fault.
      if (res.status == 400 && phases.grace_over.is_set()) error = shutting_down_error();
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
      const auto mounts = web_mounts(config.web_dir, config.three_dir);
      server.Get(R"(/.*)", [this, mounts](const httplib::Request& req, httplib::Response& res) {
        t_request.route = "/ (web page)";
        StaticAsset asset = load_web_file(mounts, req.path);
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

  // Bearer auth on /v1/*: false when the request may go on, true when it was answered 401 (its body unread).
  bool refuse_unauthorized(const httplib::Request& req, httplib::Response& res) {
    if (config.auth_token.empty() || req.path.rfind("/v1/", 0) != 0) return false;
    if (constant_time_equal(req.get_header_value("Authorization"), "Bearer " + config.auth_token)) return false;
    t_request.route = "auth";
    res.set_header("Connection", "close");  // the body (if any) is not read
    Transport::t_body_unread = true;
    write_error(res, unauthorized_error());
    return true;
  }

  // The gateway's admission of a compute request from its headers (once per request): true with the admission in
  // t_request; false when it was refused and answered, its body unread (the connection then closes).
  bool admit_from_headers(const httplib::Request& req, httplib::Response& res) {
    if (t_request.admission) return true;
    AdmissionVerdict verdict = gateway.admit(admission_query(req), t_request.request_id);
    if (verdict.admitted()) {
      t_request.admission = std::move(verdict.admission);
      return true;
    }
    res.set_header("Connection", "close");
    Transport::t_body_unread = true;
    write_response(res, verdict.refusal);
    return false;
  }

  void handle_compute(Operation op, const httplib::Request& req, httplib::Response& res,
                      const httplib::ContentReader& reader) {
    // Refused before the body is read: a full queue or an oversized Content-Length costs the server no upload.
    if (!admit_from_headers(req, res)) return;
    ComputeRequest request;
    try {
      request = read_compute_request(op, req, res, reader, config.max_parts);
    } catch (...) {
      // A body cut short by the end of the grace period is answered like a request that came too late.
      write_error(res, phases.grace_over.is_set() ? shutting_down_error() : to_api_error(std::current_exception()));
      t_request.admission.reset();
      return;
    }
    request.admission = std::move(t_request.admission);
    write_response(res, gateway.compute(std::move(request)));
  }
};

HttpServer::HttpServer(const ServerConfig& config, ModelRegistry& models, WorkerPool& pool, Metrics& metrics)
    : impl_(std::make_unique<Impl>(config, models, pool, metrics)) {}

HttpServer::~HttpServer() = default;

int HttpServer::bind() {
  auto& impl = *impl_;
  const auto& c = impl.config;
  int port = c.port;
  if (c.port == 0) {
    port = impl.server.bind_to_any_port(c.host);
    if (port <= 0) throw std::runtime_error("cannot bind to " + c.host + " (any port)");
  } else if (!impl.server.bind_to_port(c.host, c.port)) {
    throw std::runtime_error("cannot bind to " + c.host + ":" + std::to_string(c.port) + " (in use or not permitted)");
  }
  const int fd = impl.server.listening_socket();
  // httplib listens with a backlog of 5: a burst of clients overflows it, and the kernel then drops the handshake's
  // last ACK of a client that already believes it is connected (and has sent its request). A full-size queue;
  // listen() on a listening socket only changes its backlog.
  ::listen(fd, SOMAXCONN);
  impl.listener = std::make_unique<Listener>(fd);
  return port;
}

void HttpServer::serve() {
  auto& impl = *impl_;
  if (!impl.listener) throw std::logic_error("HttpServer::serve before bind");
  impl.listener->run([&impl](int sock) {
    ++impl.open_connections;
    impl.connections.enqueue([&impl, sock] {
      impl.server.serve_connection(sock, impl.phases);
      --impl.open_connections;
    });
  });
  // The listener is closed and every connection it took is queued or served: wait until each is answered and
  // closed (idle ones close at once, the rest within the grace period, see end_grace).
  impl.connections.shutdown();
}

void HttpServer::begin_shutdown() {
  impl_->gateway.begin_drain();
  impl_->phases.closing.set();
  if (impl_->listener) impl_->listener->stop_accepting();
}

void HttpServer::end_grace() {
  impl_->gateway.end_grace();
  impl_->phases.grace_over.set();
  impl_->cancels.cancel_all();
}

int HttpServer::in_flight() const { return impl_->gateway.in_flight(); }

int HttpServer::open_connections() const { return impl_->open_connections.load(); }

}  // namespace wish::server
