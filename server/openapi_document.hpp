#pragma once
// proto/openapi.json, embedded into the binary at build time (server/CMakeLists.txt), so GET /openapi.json serves
// the exact contract the binary was built against, wherever the binary runs.

#include <string_view>

namespace wish::server {

std::string_view openapi_document();

}  // namespace wish::server
