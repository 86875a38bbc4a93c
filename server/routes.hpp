#pragma once
// The service's routes, listed once: http_server.cpp registers a handler for each entry (and names the entry in the
// access log and metrics), the answer to a known path with the wrong method — 405 with an Allow header (RFC 9110
// §15.5.6) instead of httplib's 404 — is decided from the same entries, and tests/server/routes_test.cpp checks that
// they are exactly the paths of proto/openapi.json.

#include <span>
#include <string>
#include <string_view>

namespace wish::server {

enum class RouteId { Healthz, Readyz, Metrics, OpenApi, Models, Model, ModelReport, AdminReload, Describe, Classify };

struct Route {
  RouteId id;
  const char* path;     // as proto/openapi.json writes it; a "{name}" segment is any one non-empty segment
  const char* allow;    // the Allow value: "GET, HEAD" (a GET route also answers HEAD, httplib) or "POST"
};

std::span<const Route> routes();
const Route& route(RouteId id);
// The path as the HTTP library's regular expression: "{name}" segments become capture groups, the rest is literal.
std::string http_pattern(const Route& route);

// "GET, HEAD" / "POST" for a path the service routes, "" for a path it does not know. With the web page on, every
// path outside /v1/ is a GET (the page's files).
std::string allowed_methods(std::string_view path, bool web_page);

// True when `method` is in an Allow value such as "GET, HEAD".
bool method_allowed(std::string_view allow, std::string_view method);

}  // namespace wish::server
