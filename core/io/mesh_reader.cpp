// read_mesh / read_mesh_file: limits on the whole input, encoding sniffing, format detection, dispatch.
#include <fstream>
#include <sstream>

#include "core/common/errors.hpp"
#include "core/io/cursor.hpp"
#include "core/io/mesh_io.hpp"
#include "core/io/readers.hpp"

namespace wish {

namespace {

// UTF-16/32 text (Windows "Unicode" exports) is refused with a precise reason instead of "unknown format".
void refuse_wide_text(std::string_view bytes) {
  const auto byte = [&](std::size_t i) { return i < bytes.size() ? static_cast<unsigned char>(bytes[i]) : 0x100u; };
  const bool bom16 = (byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF);
  // ASCII letters interleaved with NULs: BOM-less UTF-16 ("p\0l\0y\0" or "\0p\0l\0y").
  const bool interleaved = bytes.size() >= 6 && ((byte(1) == 0 && byte(3) == 0 && byte(5) == 0 && byte(0) >= 32 && byte(0) < 128) ||
                                                 (byte(0) == 0 && byte(2) == 0 && byte(4) == 0 && byte(1) >= 32 && byte(1) < 128));
  if (bom16 || interleaved)
    throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format",
                    "the file is UTF-16 text; mesh files must be ASCII/UTF-8 text or binary (re-save it as UTF-8)",
                    {{"encoding", std::string("utf-16")}});
}

}  // namespace

ReadResult read_mesh(std::string_view bytes, const ReadOptions& options) {
  const ReadLimits& limits = options.limits;
  if (bytes.size() > limits.max_bytes)
    io_detail::throw_limit("max_bytes", static_cast<std::int64_t>(bytes.size()), static_cast<std::int64_t>(limits.max_bytes),
                           "the input is too large");
  refuse_wide_text(bytes);
  if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);  // UTF-8 byte order mark
  if (bytes.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos)
    throw InvalidInputError("empty_mesh", "the input is empty", {{"bytes", static_cast<std::int64_t>(bytes.size())}});
  const MeshFormat format = detect_format(bytes, options.hint);
  ReadResult result;
  switch (format) {
    case MeshFormat::Obj: result = io_detail::read_obj(bytes, limits); break;
    case MeshFormat::Off: result = io_detail::read_off(bytes, limits); break;
    case MeshFormat::Ply: result = io_detail::read_ply(bytes, limits); break;
    case MeshFormat::Stl: result = io_detail::read_stl(bytes, limits, io_detail::looks_binary(bytes)); break;
    case MeshFormat::Unknown:
      throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_format",
                      "the content is not a mesh in a supported format (OBJ, PLY, OFF, STL)" +
                          std::string(options.hint != MeshFormat::Unknown ? std::string(", although it was declared as ") + to_string(options.hint) : ""),
                      {{"hint", std::string(to_string(options.hint))}, {"bytes", static_cast<std::int64_t>(bytes.size())}});
  }
  result.format = format;
  if (options.hint != MeshFormat::Unknown && options.hint != format)
    result.notes.push_back(std::string("the content is ") + io_detail::format_name(format) + ", not " +
                           io_detail::format_name(options.hint) + " as its name or type said; read as " + io_detail::format_name(format));
  return result;
}

ReadResult read_mesh_file(const std::filesystem::path& path, ReadOptions options) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec)
    throw IoError("file_not_found", "cannot read " + path.string() + ": " + ec.message(), {{"path", path.string()}});
  // Checked before reading, so a huge file is never loaded.
  if (size > options.limits.max_bytes)
    io_detail::throw_limit("max_bytes", static_cast<std::int64_t>(size), static_cast<std::int64_t>(options.limits.max_bytes),
                           path.filename().string() + " is too large");
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw IoError("file_not_found", "cannot read " + path.string(), {{"path", path.string()}});
  if (options.hint == MeshFormat::Unknown) options.hint = format_from_name(path.extension().string());
  return read_mesh(bytes, options);
}

}  // namespace wish
