// TIFF stack reader through libtiff: every directory (page) is one z slice. Pages must agree in width, height and
// sample type; one sample per pixel of 8, 16 or 32 bits (unsigned, signed or IEEE float; 64-bit float too).
// Spacing, first match wins: OME-XML (ImageDescription "<OME ...>": Pixels PhysicalSizeX/Y/Z and their *Unit),
// ImageJ (ImageDescription "ImageJ=...": `unit=`, `spacing=` for z; X/YResolution give pixels per unit),
// X/YResolution with ResolutionUnit (inch, cm).
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <vector>
#include <cstring>
#include <optional>
#include <string>

#include <tiffio.h>

#include "core/common/errors.hpp"
#include "core/io/volume_readers.hpp"

namespace wish::io_detail {
namespace {

constexpr const char* kTiffFormat = "tiff";

struct MemoryFile {
  std::string_view bytes;
  toff_t position = 0;
  std::string first_error;
};

tmsize_t mem_read(thandle_t h, void* buf, tmsize_t size) {
  auto* f = static_cast<MemoryFile*>(h);
  if (size < 0) return 0;
  const toff_t left = f->position >= f->bytes.size() ? 0 : f->bytes.size() - f->position;
  const toff_t n = std::min<toff_t>(left, static_cast<toff_t>(size));
  std::memcpy(buf, f->bytes.data() + f->position, n);
  f->position += n;
  return static_cast<tmsize_t>(n);
}
tmsize_t mem_write(thandle_t, void*, tmsize_t) { return 0; }
toff_t mem_seek(thandle_t h, toff_t off, int whence) {
  auto* f = static_cast<MemoryFile*>(h);
  toff_t base = whence == SEEK_SET ? 0 : whence == SEEK_CUR ? f->position : f->bytes.size();
  f->position = base + off;  // reads past the end return 0 bytes
  return f->position;
}
int mem_close(thandle_t) { return 0; }
toff_t mem_size(thandle_t h) { return static_cast<MemoryFile*>(h)->bytes.size(); }
int mem_map(thandle_t, void**, toff_t*) { return 0; }
void mem_unmap(thandle_t, void*, toff_t) {}

int on_error(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
  auto* f = static_cast<MemoryFile*>(user);
  if (f->first_error.empty()) {
    char buf[512];
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    f->first_error = std::string(module ? module : "libtiff") + ": " + buf;
  }
  return 1;
}
int on_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

[[noreturn]] void fail(const MemoryFile& f, const std::string& message, std::int64_t page) {
  std::string m = "TIFF: " + message;
  if (!f.first_error.empty()) m += " (" + f.first_error + ")";
  throw InvalidInputError("parse_error", m, {{"format", std::string(kTiffFormat)}, {"page", page}});
}

// The number after `key` in `text` (e.g. "spacing=" -> 0.5), or nothing.
std::optional<double> number_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return std::nullopt;
  const char* start = text.c_str() + at + key.size();
  if (*start == '"') ++start;
  char* end = nullptr;
  const double v = std::strtod(start, &end);
  if (end == start || !std::isfinite(v) || v <= 0) return std::nullopt;
  return v;
}
std::optional<std::string> word_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return std::nullopt;
  std::size_t i = at + key.size();
  if (i < text.size() && text[i] == '"') ++i;
  std::string w;
  while (i < text.size() && text[i] != '"' && text[i] != '\n' && text[i] != '\r' && text[i] != ' ' && w.size() < 32) w += text[i++];
  if (w.empty()) return std::nullopt;
  return w;
}
std::string normalise_unit(std::string u) {
  if (u == "micron" || u == "µm" || u == "\xb5m" || u == "um" || u == "microns") return "um";
  if (u == "nanometer" || u == "nm") return "nm";
  if (u == "mm" || u == "millimeter") return "mm";
  return u;
}

}  // namespace

VolumeReadResult read_tiff(std::string_view bytes, const VolumeReadLimits& limits, bool probabilities) {
  MemoryFile file{bytes, 0, {}};
  TIFFOpenOptions* opts = TIFFOpenOptionsAlloc();
  TIFFOpenOptionsSetErrorHandlerExtR(opts, on_error, &file);
  TIFFOpenOptionsSetWarningHandlerExtR(opts, on_warning, &file);
  // libtiff's own allocation cap: no single buffer (strip, tile, tag) may be larger than the whole volume could be.
  TIFFOpenOptionsSetMaxSingleMemAlloc(opts, static_cast<tmsize_t>(std::min<std::int64_t>(limits.max_voxels * 8 + (1 << 20), 1ll << 32)));
  TIFF* tif = TIFFClientOpenExt("upload", "rm", &file, mem_read, mem_write, mem_seek, mem_close, mem_size, mem_map,
                                mem_unmap, opts);
  TIFFOpenOptionsFree(opts);
  if (!tif) fail(file, "cannot open the TIFF header", 0);
  struct Closer { TIFF* t; ~Closer() { TIFFClose(t); } } closer{tif};

  // Count pages first (libtiff refuses IFD loops), so the limits are checked before the volume is allocated.
  std::int64_t pages = 0;
  do {
    if (++pages > limits.max_pages)
      throw LimitExceededError("TIFF has more than " + std::to_string(limits.max_pages) + " pages",
                               {{"limit", std::string("max_pages")}, {"value", pages}, {"allowed", limits.max_pages}});
  } while (TIFFReadDirectory(tif));
  // A chain that ends in an unreadable directory is a damaged file, not a shorter stack.
  if (!file.first_error.empty()) fail(file, "the directory of page " + std::to_string(pages) + " cannot be read", pages);
  if (!TIFFSetDirectory(tif, 0)) fail(file, "cannot return to the first page", 0);

  std::uint32_t width = 0, height = 0;
  std::uint16_t bits = 0, samples = 1, format = SAMPLEFORMAT_UINT;
  if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &width) || !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &height))
    fail(file, "page 0 has no ImageWidth/ImageLength", 0);
  TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
  VoxelType type{};
  bool known = samples == 1;
  if (format == SAMPLEFORMAT_UINT && bits == 8) type = VoxelType::UInt8;
  else if (format == SAMPLEFORMAT_UINT && bits == 16) type = VoxelType::UInt16;
  else if (format == SAMPLEFORMAT_UINT && bits == 32) type = VoxelType::UInt32;
  else if (format == SAMPLEFORMAT_INT && bits == 8) type = VoxelType::Int8;
  else if (format == SAMPLEFORMAT_INT && bits == 16) type = VoxelType::Int16;
  else if (format == SAMPLEFORMAT_INT && bits == 32) type = VoxelType::Int32;
  else if (format == SAMPLEFORMAT_IEEEFP && bits == 32) type = VoxelType::Float32;
  else if (format == SAMPLEFORMAT_IEEEFP && bits == 64) type = VoxelType::Float64;
  else known = false;
  if (!known)
    throw InvalidInputError("unsupported_datatype", "TIFF pages of " + std::to_string(samples) + " sample(s) of " +
                                                        std::to_string(bits) + " bits (format " + std::to_string(format) +
                                                        ") are not a label image: one 8/16/32-bit integer or float sample per pixel",
                            {{"format", std::string(kTiffFormat)}, {"datatype", std::to_string(bits) + "-bit"}});
  const std::int64_t n = checked_voxel_count(width, height, pages, limits, kTiffFormat);

  VolumeReadResult r;
  r.format = VolumeFormat::Tiff;
  r.datatype = to_string(type);
  r.image.dims = {width, height, pages};
  r.image.labels.resize(static_cast<std::size_t>(n));
  if (probabilities) r.image.probability_scale = volume::LabelImage::kProbabilityScale;
  const std::size_t bs = static_cast<std::size_t>(byte_size(type));
  std::vector<unsigned char> buffer;
  for (std::int64_t z = 0; z < pages; ++z) {
    if (z > 0 && !TIFFReadDirectory(tif)) fail(file, "cannot read page " + std::to_string(z), z);
    std::uint32_t w = 0, hgt = 0;
    std::uint16_t b = 0, s = 1, fmt = SAMPLEFORMAT_UINT;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &hgt);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &b);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &s);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &fmt);
    if (w != width || hgt != height || b != bits || s != samples || fmt != format)
      fail(file, "page " + std::to_string(z) + " is " + std::to_string(w) + " x " + std::to_string(hgt) + " of " +
                     std::to_string(b) + " bits, page 0 is " + std::to_string(width) + " x " + std::to_string(height) +
                     " of " + std::to_string(bits) + " bits", z);
    std::uint32_t* slice = r.image.labels.data() + static_cast<std::size_t>(z) * width * height;
    if (TIFFIsTiled(tif)) {
      std::uint32_t tw = 0, th = 0;
      TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw);
      TIFFGetField(tif, TIFFTAG_TILELENGTH, &th);
      if (tw == 0 || th == 0) fail(file, "tile size is 0", z);
      const tmsize_t tile_bytes = TIFFTileSize(tif);
      if (tile_bytes <= 0 || static_cast<std::uint64_t>(tile_bytes) < static_cast<std::uint64_t>(tw) * th * bs)
        fail(file, "tile size does not match the tile dimensions", z);
      buffer.resize(static_cast<std::size_t>(tile_bytes));
      std::vector<std::uint32_t> row(tw);
      for (std::uint32_t ty = 0; ty < height; ty += th)
        for (std::uint32_t tx = 0; tx < width; tx += tw) {
          if (TIFFReadTile(tif, buffer.data(), tx, ty, 0, 0) < 0)
            fail(file, "cannot decode the tile at " + std::to_string(tx) + ", " + std::to_string(ty), z);
          for (std::uint32_t yy = 0; yy < th && ty + yy < height; ++yy) {
            const std::uint32_t cols = std::min(tw, width - tx);
            convert_labels(buffer.data() + static_cast<std::size_t>(yy) * tw * bs, cols, type, false, row.data(),
                           (z * height + ty + yy) * static_cast<std::int64_t>(width) + tx, kTiffFormat,
                           r.image.probability_scale);
            std::memcpy(slice + static_cast<std::size_t>(ty + yy) * width + tx, row.data(), cols * sizeof(std::uint32_t));
          }
        }
    } else {
      const tmsize_t line = TIFFScanlineSize(tif);
      if (line <= 0 || static_cast<std::uint64_t>(line) < static_cast<std::uint64_t>(width) * bs)
        fail(file, "scanline size does not match the width", z);
      buffer.resize(static_cast<std::size_t>(line));
      for (std::uint32_t y = 0; y < height; ++y) {
        if (TIFFReadScanline(tif, buffer.data(), y, 0) < 0) fail(file, "cannot decode row " + std::to_string(y), z);
        // libtiff returns samples in the machine's byte order.
        convert_labels(buffer.data(), width, type, false, slice + static_cast<std::size_t>(y) * width,
                       (z * height + y) * static_cast<std::int64_t>(width), kTiffFormat, r.image.probability_scale);
      }
    }
  }

  // Spacing and unit from the first page's metadata.
  TIFFSetDirectory(tif, 0);
  char* desc_c = nullptr;
  const std::string desc = TIFFGetField(tif, TIFFTAG_IMAGEDESCRIPTION, &desc_c) && desc_c ? std::string(desc_c) : std::string();
  float xres = 0, yres = 0;
  std::uint16_t res_unit = RESUNIT_INCH;
  const bool has_res = TIFFGetField(tif, TIFFTAG_XRESOLUTION, &xres) && TIFFGetField(tif, TIFFTAG_YRESOLUTION, &yres) &&
                       std::isfinite(xres) && std::isfinite(yres) && xres > 0 && yres > 0;
  TIFFGetFieldDefaulted(tif, TIFFTAG_RESOLUTIONUNIT, &res_unit);
  if (desc.find("<OME") != std::string::npos) {
    const auto sx = number_after(desc, "PhysicalSizeX=");
    const auto sy = number_after(desc, "PhysicalSizeY=");
    const auto sz = number_after(desc, "PhysicalSizeZ=");
    if (sx) r.image.spacing(0) = *sx;
    if (sy) r.image.spacing(1) = *sy;
    if (sz) r.image.spacing(2) = *sz;
    r.image.unit = normalise_unit(word_after(desc, "PhysicalSizeXUnit=").value_or("um"));  // OME's default is µm
    r.spacing_from_file = sx && sy && sz;
    r.notes.push_back("spacing from OME-XML");
  } else if (desc.rfind("ImageJ=", 0) == 0) {
    if (has_res) r.image.spacing = Eigen::Vector3d(1.0 / xres, 1.0 / yres, 1.0);
    const auto sz = number_after(desc, "\nspacing=");
    if (sz) r.image.spacing(2) = *sz;
    r.image.unit = normalise_unit(word_after(desc, "\nunit=").value_or(""));
    r.spacing_from_file = has_res && sz;
    r.notes.push_back("spacing from ImageJ metadata");
  } else if (has_res && (res_unit == RESUNIT_CENTIMETER || res_unit == RESUNIT_INCH)) {
    const double per_um = res_unit == RESUNIT_CENTIMETER ? 1e4 : 25.4e3;  // micrometres per unit
    r.image.spacing = Eigen::Vector3d(per_um / xres, per_um / yres, 1.0);
    r.image.unit = "um";
    r.notes.push_back("x, y spacing from the resolution tags; z spacing unknown, 1 um assumed");
  } else {
    r.notes.push_back("no spacing in the TIFF: voxel size 1 assumed");
  }
  if (!(r.image.spacing.array() > 0).all() || !r.image.spacing.allFinite()) r.image.spacing.setOnes();
  return r;
}

}  // namespace wish::io_detail
