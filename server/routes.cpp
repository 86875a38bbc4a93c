#include "server/routes.hpp"

#include <algorithm>
#include <string_view>

namespace wish::server {

namespace {

constexpr Route kRoutes[] = {
    {RouteId::Healthz, "/healthz", "GET, HEAD"},
    {RouteId::Readyz, "/readyz", "GET, HEAD"},
    {RouteId::Metrics, "/metrics", "GET, HEAD"},
    {RouteId::OpenApi, "/openapi.json", "GET, HEAD"},
    {RouteId::Models, "/v1/models", "GET, HEAD"},
    {RouteId::Model, "/v1/models/{name}", "GET, HEAD"},
    {RouteId::ModelReport, "/v1/models/{name}/report", "GET, HEAD"},
    {RouteId::AdminReload, "/v1/admin/reload", "POST"},
    {RouteId::Describe, "/v1/describe", "POST"},
    {RouteId::Classify, "/v1/classify", "POST"},
};

// The next '/'-separated segment of `s` (after its leading '/'), removed from `s`.
std::string_view next_segment(std::string_view& s) {
  if (!s.empty() && s.front() == '/') s.remove_prefix(1);
  const std::size_t end = std::min(s.find('/'), s.size());
  const std::string_view segment = s.substr(0, end);
  s.remove_prefix(end);
  return segment;
}

bool matches(std::string_view pattern, std::string_view path) {
  while (!pattern.empty() || !path.empty()) {
    if (pattern.empty() || path.empty() || path.front() != '/') return false;
    const std::string_view want = next_segment(pattern);
    const std::string_view got = next_segment(path);
    if (want.starts_with('{') ? got.empty() : want != got) return false;
  }
  return true;
}

}  // namespace

std::span<const Route> routes() { return kRoutes; }

std::string http_pattern(const Route& r) {
  std::string out;
  std::string_view rest = r.path;
  while (!rest.empty()) {
    const std::string_view segment = next_segment(rest);
    out += '/';
    if (segment.starts_with('{')) {
      out += "([^/]+)";
      continue;
    }
    for (const char c : segment) {
      if (std::string_view(".+*?()[]{}|^$\\").find(c) != std::string_view::npos) out += '\\';
      out += c;
    }
  }
  return out;
}

const Route& route(RouteId id) {
  for (const auto& r : kRoutes)
    if (r.id == id) return r;
  return kRoutes[0];  // unreachable: every RouteId has an entry (routes_test)
}

std::string allowed_methods(std::string_view path, bool web_page) {
  for (const auto& route : kRoutes)
    if (matches(route.path, path)) return route.allow;
  if (web_page && path.substr(0, 4) != "/v1/" && path != "/v1") return "GET, HEAD";
  return "";
}

bool method_allowed(std::string_view allow, std::string_view method) {
  std::size_t start = 0;
  while (start < allow.size()) {
    std::size_t end = allow.find(',', start);
    if (end == std::string_view::npos) end = allow.size();
    std::string_view item = allow.substr(start, end - start);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item == method) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace wish::server
