// Format names and content-based format detection.
//
// Detection looks at the content only: the PLY magic line, the binary STL size equation, an OFF header keyword,
// "solid" for ASCII STL, and OBJ statements. When several formats fit (a binary STL whose 80-byte header happens
// to read "OFF"...), the hint (extension / Content-Type) picks among them; it never overrides the content.
#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <string>

#include "core/io/cursor.hpp"
#include "core/io/mesh_io.hpp"
#include "core/io/readers.hpp"

namespace wish {

const char* to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Ply: return "ply";
    case MeshFormat::Off: return "off";
    case MeshFormat::Stl: return "stl";
    case MeshFormat::Unknown: break;
  }
  return "unknown";
}

MeshFormat format_from_name(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // MIME types: "model/obj", "application/ply", "model/x.stl-binary", "application/sla" (STL), "text/plain; ..." etc.
  if (const auto semi = s.find(';'); semi != std::string::npos) s.resize(semi);
  while (!s.empty() && io_detail::is_space(s.back())) s.pop_back();
  if (s == "application/sla" || s == "application/vnd.ms-pki.stl") return MeshFormat::Stl;
  if (const auto slash = s.rfind('/'); slash != std::string::npos) s = s.substr(slash + 1);
  if (const auto dot = s.rfind('.'); dot != std::string::npos) s = s.substr(dot + 1);  // "mesh.OBJ", ".obj"
  for (const char* prefix : {"x-", "x."}) if (s.rfind(prefix, 0) == 0) s = s.substr(2);
  if (const auto dash = s.find('-'); dash != std::string::npos) s.resize(dash);        // "stl-binary"
  if (s == "obj") return MeshFormat::Obj;
  if (s == "ply") return MeshFormat::Ply;
  if (s == "off") return MeshFormat::Off;
  if (s == "stl") return MeshFormat::Stl;
  return MeshFormat::Unknown;
}

namespace io_detail {

bool is_binary_stl_size(std::string_view bytes) {
  if (bytes.size() < 84) return false;
  std::uint32_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(bytes[80 + static_cast<std::size_t>(i)]);
  return 84 + 50ull * n == bytes.size();
}

bool looks_binary(std::string_view bytes, std::size_t window) {
  const std::size_t n = std::min(bytes.size(), window);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\v' && c != '\f')) return true;
  }
  return false;
}

}  // namespace io_detail

namespace {

bool starts_with_keyword(std::string_view text, std::string_view keyword) {
  if (text.size() < keyword.size()) return false;
  for (std::size_t i = 0; i < keyword.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != keyword[i]) return false;
  return text.size() == keyword.size() || io_detail::is_space(text[keyword.size()]) || text[keyword.size()] == '\n';
}

// The first token that is not blank or a '#' comment, within the first few KB.
std::string_view first_token(std::string_view bytes) {
  std::size_t i = 0;
  const std::size_t end = std::min<std::size_t>(bytes.size(), 1 << 16);
  while (i < end) {
    if (io_detail::is_space(bytes[i]) || bytes[i] == '\n') { ++i; continue; }
    if (bytes[i] == '#') {
      while (i < end && bytes[i] != '\n') ++i;
      continue;
    }
    std::size_t j = i;
    while (j < end && !io_detail::is_space(bytes[j]) && bytes[j] != '\n' && bytes[j] != '#') ++j;
    return bytes.substr(i, j - i);
  }
  return {};
}

// [ST][C][N][4][n]OFF, the keyword family of the OFF format (Geomview).
bool is_off_keyword(std::string_view token) {
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
  std::string_view prefix = token.substr(0, token.size() - 3);
  for (std::string_view part : {"ST", "C", "N", "4", "n"})
    if (prefix.substr(0, part.size()) == part) prefix.remove_prefix(part.size());
  return prefix.empty();
}

bool is_obj_keyword(std::string_view token) {
  static constexpr std::array<std::string_view, 16> keywords = {"v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s",
                                                               "mtllib", "usemtl", "usemap", "maplib", "cstype", "deg"};
  return std::find(keywords.begin(), keywords.end(), token) != keywords.end();
}

}  // namespace

MeshFormat detect_format(std::string_view bytes, MeshFormat hint) {
  std::vector<MeshFormat> candidates;  // in order of confidence
  if (bytes.size() >= 4 && bytes.substr(0, 3) == "ply" && (bytes[3] == '\n' || bytes[3] == '\r')) return MeshFormat::Ply;
  const bool binary_stl_size = io_detail::is_binary_stl_size(bytes);
  const bool text = !io_detail::looks_binary(bytes);
  // Binary STL float data practically always contains control bytes; text that satisfies the size equation by
  // chance is text first.
  if (binary_stl_size && !text) candidates.push_back(MeshFormat::Stl);
  if (text) {
    const std::string_view token = first_token(bytes);
    if (is_off_keyword(token)) candidates.push_back(MeshFormat::Off);
    if (starts_with_keyword(bytes, "solid")) candidates.push_back(MeshFormat::Stl);
    if (is_obj_keyword(token)) candidates.push_back(MeshFormat::Obj);
    if (binary_stl_size) candidates.push_back(MeshFormat::Stl);
  } else if (bytes.substr(0, 5) == "solid" || (bytes.size() >= 84 && hint == MeshFormat::Stl)) {
    // Binary content that is not a well-formed binary STL: most likely a truncated or padded one; the STL reader
    // reports exactly what is wrong with it.
    candidates.push_back(MeshFormat::Stl);
  }
  if (candidates.empty()) return MeshFormat::Unknown;
  if (std::find(candidates.begin(), candidates.end(), hint) != candidates.end()) return hint;
  return candidates.front();
}

}  // namespace wish
