#pragma once
// The web page's files served from disk at GET /: httplib-free, so that the lookup rules are testable and
// http_server.cpp only copies the answer into its response. The page has no build step: its own files are web/src
// as they are, and the three.js it imports is Debian's libjs-three where the package installed it, mounted under
// kThreeUrlPrefix (web/src/index.html's import map points there).
//
// Rules: the URL path (already percent-decoded) maps to a file under `root`; "/" and paths ending in "/" mean
// index.html. Refused (404, never a read outside `root`): empty or ".." segments, segments starting with "." (no
// dotfiles), backslashes and NUL bytes, and anything whose canonical path (symlinks resolved) leaves the canonical
// root. Content type from the extension (unknown: application/octet-stream). Cache-Control: index.html "no-cache"
// (a new build is picked up at once), other files "public, max-age=3600".

#include <filesystem>
#include <string>
#include <vector>

namespace wish::server {

struct StaticAsset {
  int status = 404;            // 200, or 404 (not found or refused)
  std::string body;            // the file's bytes when 200
  std::string content_type;
  std::string cache_control;
};

StaticAsset load_static_asset(const std::filesystem::path& root, const std::string& url_path);

// A directory served under a URL prefix ("/" for the page itself).
struct WebMount {
  std::string url_prefix;  // starts and ends with "/"
  std::filesystem::path root;
};

// Where the page's import map finds three.js: the root of Debian's libjs-three (/usr/share/javascript/three).
inline constexpr const char* kThreeUrlPrefix = "/vendor/three/";

// The mounts of a page directory and a three.js directory (either may be empty: not mounted).
std::vector<WebMount> web_mounts(const std::filesystem::path& page_dir, const std::filesystem::path& three_dir);

// The mount with the longest prefix of `url_path` answers, with the rest of the path under its root (the rules
// above); a path under a mount that lacks the file is 404, never looked up in a shorter mount.
StaticAsset load_web_file(const std::vector<WebMount>& mounts, const std::string& url_path);

// "text/html; charset=utf-8", "text/javascript; charset=utf-8", ... by the extension of `file_name`.
std::string content_type_for(const std::string& file_name);

}  // namespace wish::server
