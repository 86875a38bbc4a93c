#include "server/logging.hpp"

#include <memory>

#include <nlohmann/json.hpp>
#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace wish::server {

namespace {

bool g_json = false;
std::shared_ptr<spdlog::logger> g_access;

// %* : the message as a JSON string literal (escaped, invalid UTF-8 replaced), so every line is one JSON object.
class JsonMessageFlag : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    const std::string text = nlohmann::json(std::string(msg.payload.data(), msg.payload.size()))
                                 .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    dest.append(text.data(), text.data() + text.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<JsonMessageFlag>(); }
};

}  // namespace

void configure_logging(bool json, const std::string& level) {
  g_json = json;
  // Formatters live on sinks in spdlog, so each logger gets its own stderr sink (they share the console mutex, so
  // lines never interleave).
  auto main = std::make_shared<spdlog::logger>("wish", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  g_access = std::make_shared<spdlog::logger>("access", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  if (json) {
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    formatter->add_flag<JsonMessageFlag>('*').set_pattern(
        R"({"time":"%Y-%m-%dT%H:%M:%S.%e%z","level":"%l","logger":"%n","message":%*})");
    main->set_formatter(std::move(formatter));
    g_access->set_pattern("%v");  // access lines are complete JSON objects already
  } else {
    main->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
    g_access->set_pattern("%Y-%m-%d %H:%M:%S.%e access %v");
  }
  main->set_level(spdlog::level::from_str(level));
  main->flush_on(spdlog::level::trace);  // a service log must not lose its last lines on a crash or kill
  g_access->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(main);
}

void log_access(const AccessRecord& r) {
  if (!g_access) return;
  if (g_json) {
    nlohmann::json line{{"type", "access"},       {"request_id", r.request_id}, {"method", r.method},
                        {"path", r.path},         {"route", r.route},           {"status", r.status},
                        {"bytes_in", r.bytes_in}, {"bytes_out", r.bytes_out},   {"duration_ms", r.seconds * 1e3}};
    if (r.parts > 0) line["parts"] = r.parts;
    if (r.vertices >= 0) line["vertices"] = r.vertices;
    if (r.faces >= 0) line["faces"] = r.faces;
    if (!r.error_code.empty()) line["error"] = r.error_code;
    g_access->info(line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  g_access->info("request_id={} {} {} route={} status={} bytes_in={} bytes_out={} parts={} vertices={} faces={} "
                 "duration_ms={:.2f}{}{}",
                 r.request_id, r.method, r.path, r.route, r.status, r.bytes_in, r.bytes_out, r.parts, r.vertices,
                 r.faces, r.seconds * 1e3, r.error_code.empty() ? "" : " error=", r.error_code);
}

}  // namespace wish::server
