#pragma once
// The service's routes as data, for the answer to a known path with the wrong method: 405 with an Allow header
// (RFC 9110 §15.5.6) instead of httplib's 404. http_server.cpp registers the handlers; this table must list the same
// paths (tests/server/routes_test.cpp and the Python API test check both sides).

#include <string>
#include <string_view>

namespace wish::server {

// "GET, HEAD" / "POST" for a path the service routes, "" for a path it does not know. With the web page on, every
// path outside /v1/ is a GET (the page's files). A GET route also answers HEAD (httplib).
std::string allowed_methods(std::string_view path, bool web_page);

// True when `method` is in an Allow value such as "GET, HEAD".
bool method_allowed(std::string_view allow, std::string_view method);

}  // namespace wish::server
