#pragma once
// The web page's files (web/, built into a directory by web/build.mjs) served from disk at GET /: httplib-free, so
// that the lookup rules are testable and http_server.cpp only copies the answer into its response.
//
// Rules: the URL path (already percent-decoded) maps to a file under `root`; "/" and paths ending in "/" mean
// index.html. Refused (404, never a read outside `root`): empty or ".." segments, segments starting with "." (no
// dotfiles), backslashes and NUL bytes, and anything whose canonical path (symlinks resolved) leaves the canonical
// root. Content type from the extension (unknown: application/octet-stream). Cache-Control: index.html "no-cache"
// (a new build is picked up at once), other files "public, max-age=3600".

#include <filesystem>
#include <string>

namespace wish::server {

struct StaticAsset {
  int status = 404;            // 200, or 404 (not found or refused)
  std::string body;            // the file's bytes when 200
  std::string content_type;
  std::string cache_control;
};

StaticAsset load_static_asset(const std::filesystem::path& root, const std::string& url_path);

// "text/html; charset=utf-8", "text/javascript; charset=utf-8", ... by the extension of `file_name`.
std::string content_type_for(const std::string& file_name);

}  // namespace wish::server
