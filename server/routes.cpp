#include "server/routes.hpp"

namespace wish::server {

namespace {

struct Route {
  const char* path;  // exact, or ending in "/{}" for one more path segment
  const char* allow;
};

constexpr Route kRoutes[] = {
    {"/healthz", "GET, HEAD"},         {"/readyz", "GET, HEAD"},        {"/metrics", "GET, HEAD"},
    {"/openapi.json", "GET, HEAD"},    {"/v1/models", "GET, HEAD"},     {"/v1/models/{}", "GET, HEAD"},
    {"/v1/admin/reload", "POST"},      {"/v1/describe", "POST"},        {"/v1/classify", "POST"},
};

bool matches(std::string_view pattern, std::string_view path) {
  constexpr std::string_view segment = "/{}";
  if (pattern.size() >= segment.size() && pattern.substr(pattern.size() - segment.size()) == segment) {
    const std::string_view prefix = pattern.substr(0, pattern.size() - 2);  // keeps the '/'
    if (path.size() <= prefix.size() || path.substr(0, prefix.size()) != prefix) return false;
    return path.substr(prefix.size()).find('/') == std::string_view::npos;
  }
  return pattern == path;
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
