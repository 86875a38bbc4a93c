#include "server/static_assets.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <system_error>

namespace wish::server {

namespace {

// Splits "/a/b/" into segments and refuses what could leave the root or reach hidden files.
bool safe_relative_path(const std::string& url_path, std::filesystem::path& out) {
  if (url_path.empty() || url_path.front() != '/') return false;
  if (url_path.find('\0') != std::string::npos || url_path.find('\\') != std::string::npos) return false;
  std::string path = url_path.substr(1);
  if (path.empty() || path.back() == '/') path += "index.html";
  std::filesystem::path rel;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto slash = path.find('/', start);
    const std::string segment = path.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (segment.empty() || segment.front() == '.') return false;  // "//", ".", "..", dotfiles
    rel /= segment;
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  out = rel;
  return true;
}

}  // namespace

std::string content_type_for(const std::string& file_name) {
  static const std::map<std::string, std::string> types{
      {".html", "text/html; charset=utf-8"},  {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},          {".svg", "image/svg+xml"},
      {".png", "image/png"},                  {".ico", "image/x-icon"},
      {".txt", "text/plain; charset=utf-8"},  {".map", "application/json"},
      {".wasm", "application/wasm"}};
  const auto ext = std::filesystem::path(file_name).extension().string();
  const auto it = types.find(ext);
  return it == types.end() ? "application/octet-stream" : it->second;
}

StaticAsset load_static_asset(const std::filesystem::path& root, const std::string& url_path) {
  StaticAsset asset;
  std::filesystem::path rel;
  if (root.empty() || !safe_relative_path(url_path, rel)) return asset;
  std::error_code ec;
  const auto canonical_root = std::filesystem::canonical(root, ec);
  if (ec) return asset;
  const auto file = std::filesystem::weakly_canonical(canonical_root / rel, ec);
  if (ec || !std::filesystem::is_regular_file(file, ec)) return asset;
  // A symlink inside the root must not lead out of it.
  const auto [root_end, file_it] = std::mismatch(canonical_root.begin(), canonical_root.end(), file.begin(), file.end());
  if (root_end != canonical_root.end()) return asset;
  std::ifstream in(file, std::ios::binary);
  if (!in) return asset;
  asset.body.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) return StaticAsset{};
  asset.status = 200;
  asset.content_type = content_type_for(file.filename().string());
  asset.cache_control = file.filename() == "index.html" ? "no-cache" : "public, max-age=3600";
  return asset;
}

std::vector<WebMount> web_mounts(const std::filesystem::path& page_dir, const std::filesystem::path& three_dir) {
  std::vector<WebMount> mounts;
  if (!page_dir.empty()) mounts.push_back({"/", page_dir});
  if (!three_dir.empty()) mounts.push_back({kThreeUrlPrefix, three_dir});
  return mounts;
}

StaticAsset load_web_file(const std::vector<WebMount>& mounts, const std::string& url_path) {
  const WebMount* best = nullptr;
  for (const auto& mount : mounts)
    if (url_path.starts_with(mount.url_prefix) && (!best || mount.url_prefix.size() > best->url_prefix.size()))
      best = &mount;
  if (!best) return StaticAsset{};
  // The prefix's last "/" starts the path inside the mount's root.
  return load_static_asset(best->root, url_path.substr(best->url_prefix.size() - 1));
}

}  // namespace wish::server
