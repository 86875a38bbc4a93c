// Writers. Text formats print coordinates in the shortest form that reads back to the same double
// (std::to_chars), so write -> read is exact. Binary PLY stores double x/y/z and int indices (exact); binary STL
// is float32 by definition, so it is exact only for coordinates that are floats already.
#include <array>
#include <bit>
#include <charconv>
#include <cstring>
#include <fstream>

#include <Eigen/Geometry>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"

namespace wish {

namespace {

void append_number(std::string& out, double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

void append_number(std::string& out, long long value) {
  char buffer[24];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

template <class T>
void append_binary(std::string& out, T value, bool big_endian) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big))
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  out.append(raw, sizeof(T));
}

void append_xyz(std::string& out, const Mesh& mesh, Eigen::Index v) {
  for (int k = 0; k < 3; ++k) {
    if (k) out += ' ';
    append_number(out, mesh.vertices(v, k));
  }
}

// The text body of OBJ, OFF and ASCII PLY: one "<vertex_prefix>x y z" line per vertex, then one
// "<face_prefix> i j k" line per face, indices counted from `first_index` (OBJ: "v ", "f", 1; OFF/PLY: "", "3", 0).
void append_text_body(std::string& out, const Mesh& mesh, const char* vertex_prefix, char face_prefix,
                      long long first_index) {
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    out += vertex_prefix;
    append_xyz(out, mesh, v);
    out += '\n';
  }
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    out += face_prefix;
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_number(out, static_cast<long long>(mesh.faces(f, k)) + first_index);
    }
    out += '\n';
  }
}

std::string write_obj(const Mesh& mesh) {
  std::string out = "# written by WISH\n";
  append_text_body(out, mesh, "v ", 'f', 1);  // OBJ is 1-based
  return out;
}

std::string write_off(const Mesh& mesh) {
  std::string out = "OFF\n";
  append_number(out, static_cast<long long>(mesh.vertex_count()));
  out += ' ';
  append_number(out, static_cast<long long>(mesh.face_count()));
  out += " 0\n";
  append_text_body(out, mesh, "", '3', 0);
  return out;
}

std::string write_ply(const Mesh& mesh, MeshEncoding encoding) {
  std::string out = "ply\nformat ";
  out += encoding == MeshEncoding::Ascii ? "ascii" : encoding == MeshEncoding::BinaryBigEndian ? "binary_big_endian" : "binary_little_endian";
  out += " 1.0\ncomment written by WISH\nelement vertex " + std::to_string(mesh.vertex_count()) +
         "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(mesh.face_count()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
  if (encoding == MeshEncoding::Ascii) {
    append_text_body(out, mesh, "", '3', 0);
    return out;
  }
  const bool big = encoding == MeshEncoding::BinaryBigEndian;
  out.reserve(out.size() + static_cast<std::size_t>(mesh.vertex_count()) * 24 + static_cast<std::size_t>(mesh.face_count()) * 13);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k) append_binary(out, mesh.vertices(v, k), big);
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    append_binary<std::uint8_t>(out, 3, big);
    for (int k = 0; k < 3; ++k) append_binary<std::int32_t>(out, mesh.faces(f, k), big);
  }
  return out;
}

Eigen::Vector3d face_normal(const Mesh& mesh, Eigen::Index f) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)), b = mesh.vertices.row(mesh.faces(f, 1)),
                        c = mesh.vertices.row(mesh.faces(f, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
}

std::string write_stl(const Mesh& mesh, MeshEncoding encoding) {
  if (encoding == MeshEncoding::Ascii) {
    std::string out = "solid wish\n";
    for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
      const Eigen::Vector3d n = face_normal(mesh, f);
      out += "  facet normal ";
      for (int k = 0; k < 3; ++k) {
        if (k) out += ' ';
        append_number(out, n[k]);
      }
      out += "\n    outer loop\n";
      for (int k = 0; k < 3; ++k) {
        out += "      vertex ";
        append_xyz(out, mesh, mesh.faces(f, k));
        out += '\n';
      }
      out += "    endloop\n  endfacet\n";
    }
    out += "endsolid wish\n";
    return out;
  }
  // Binary STL is little endian by definition, whatever encoding was asked for. The header must not start with
  // "solid", which would make naive readers take it for ASCII.
  std::string out(80, ' ');
  const char header[] = "binary STL written by WISH";
  std::memcpy(out.data(), header, sizeof header - 1);
  append_binary<std::uint32_t>(out, static_cast<std::uint32_t>(mesh.face_count()), false);
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d n = face_normal(mesh, f);
    for (int k = 0; k < 3; ++k) append_binary(out, static_cast<float>(n[k]), false);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) append_binary(out, static_cast<float>(mesh.vertices(mesh.faces(f, c), k)), false);
    append_binary<std::uint16_t>(out, 0, false);
  }
  return out;
}

}  // namespace

std::string write_mesh(const Mesh& mesh, MeshFormat format, MeshEncoding encoding) {
  switch (format) {
    case MeshFormat::Obj: return write_obj(mesh);  // ASCII only: the encoding does not apply
    case MeshFormat::Off: return write_off(mesh);
    case MeshFormat::Ply: return write_ply(mesh, encoding);
    case MeshFormat::Stl: return write_stl(mesh, encoding);
    case MeshFormat::Unknown: break;
  }
  throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format", "cannot write a mesh in an unknown format");
}

void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path, MeshEncoding encoding) {
  const MeshFormat format = format_from_name(path.extension().string());
  if (format == MeshFormat::Unknown)
    throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format",
                    "cannot tell the mesh format from the file name " + path.filename().string() + " (use .obj, .ply, .off or .stl)",
                    {{"path", path.string()}});
  const std::string bytes = write_mesh(mesh, format, encoding);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush())
    throw IoError("write_failed", "cannot write " + path.string(), {{"path", path.string()}});
}

}  // namespace wish
