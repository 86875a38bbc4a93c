#include "server/routes.hpp"

#include <algorithm>

namespace wish::server {

namespace {

struct Route {
  const char* path;  // segments; "{}" is any one non-empty segment
  const char* allow;
};

constexpr Route kRoutes[] = {
    {"/healthz", "GET, HEAD"},         {"/readyz", "GET, HEAD"},        {"/metrics", "GET, HEAD"},
    {"/openapi.json", "GET, HEAD"},    {"/v1/models", "GET, HEAD"},     {"/v1/models/{}", "GET, HEAD"},
    {"/v1/models/{}/report", "GET, HEAD"},
    {"/v1/admin/reload", "POST"},      {"/v1/describe", "POST"},        {"/v1/classify", "POST"},
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
    if (want == "{}" ? got.empty() : want != got) return false;
  }
  return true;
}

}  // namespace

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
