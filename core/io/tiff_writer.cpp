// TIFF label images through libtiff (core/io/label_image_writers.hpp): one 8-bit palette page per z slice, deflate,
// ImageJ's ImageDescription (images, slices, unit, spacing) and X/YResolution = 1 / voxel size, which is what Fiji
// and the WISH reader (tiff_reader.cpp) take the voxel size from. Pages are written as they are made.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <tiffio.h>

#include "core/common/errors.hpp"
#include "core/io/label_image_writers.hpp"

namespace wish {
namespace {

// A growable in-memory file for TIFFClientOpen (libtiff seeks back to patch offsets, so it needs random access).
struct MemoryOut {
  std::string bytes;
  toff_t position = 0;
};

tmsize_t out_read(thandle_t h, void* buf, tmsize_t size) {
  auto* m = static_cast<MemoryOut*>(h);
  const toff_t left = m->position >= m->bytes.size() ? 0 : m->bytes.size() - m->position;
  const toff_t n = std::min<toff_t>(left, static_cast<toff_t>(size));
  std::memcpy(buf, m->bytes.data() + m->position, n);
  m->position += n;
  return static_cast<tmsize_t>(n);
}
tmsize_t out_write(thandle_t h, void* buf, tmsize_t size) {
  auto* m = static_cast<MemoryOut*>(h);
  const auto n = static_cast<std::size_t>(size);
  if (m->position + n > m->bytes.size()) m->bytes.resize(m->position + n);
  std::memcpy(m->bytes.data() + m->position, buf, n);
  m->position += n;
  return size;
}
toff_t out_seek(thandle_t h, toff_t off, int whence) {
  auto* m = static_cast<MemoryOut*>(h);
  const toff_t base = whence == SEEK_SET ? 0 : whence == SEEK_CUR ? m->position : m->bytes.size();
  m->position = base + off;
  return m->position;
}
int out_close(thandle_t) { return 0; }
toff_t out_size(thandle_t h) { return static_cast<MemoryOut*>(h)->bytes.size(); }
int out_map(thandle_t, void**, toff_t*) { return 0; }
void out_unmap(thandle_t, void*, toff_t) {}

[[noreturn]] void tiff_write_failed(const std::string& what) {
  throw IoError("write_failed", "TIFF label image: " + what + " (libtiff)");
}

std::string imagej_description(const LabelImageShape& shape) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "ImageJ=1.11a\nimages=%lld\nslices=%lld\nunit=%s\nspacing=%.17g\nloop=false\n",
                static_cast<long long>(shape.dims[2]), static_cast<long long>(shape.dims[2]),
                shape.unit.empty() ? "pixel" : (shape.unit == "um" ? "micron" : shape.unit.c_str()), shape.spacing(2));
  return buf;
}

void write_pages(TIFF* tif, const LabelImageShape& shape, const LabelRowSource& source,
                 const std::vector<std::array<std::uint8_t, 3>>& palette) {
  const auto nx = static_cast<std::uint32_t>(shape.dims[0]), ny = static_cast<std::uint32_t>(shape.dims[1]);
  // Palette entries are 16-bit (value × 257 maps 255 to 65535).
  std::vector<std::uint16_t> red(256, 0), green(256, 0), blue(256, 0);
  for (std::size_t v = 0; v < palette.size() && v < 256; ++v) {
    red[v] = static_cast<std::uint16_t>(palette[v][0] * 257);
    green[v] = static_cast<std::uint16_t>(palette[v][1] * 257);
    blue[v] = static_cast<std::uint16_t>(palette[v][2] * 257);
  }
  const std::string description = imagej_description(shape);
  std::vector<std::uint8_t> slice(static_cast<std::size_t>(nx) * ny);
  for (std::int64_t z = 0; z < shape.dims[2]; ++z) {
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, nx);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, ny);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_UINT);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_PALETTE);
    TIFFSetField(tif, TIFFTAG_COLORMAP, red.data(), green.data(), blue.data());
    TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, ny);
    TIFFSetField(tif, TIFFTAG_RESOLUTIONUNIT, RESUNIT_NONE);
    TIFFSetField(tif, TIFFTAG_XRESOLUTION, static_cast<float>(1.0 / shape.spacing(0)));
    TIFFSetField(tif, TIFFTAG_YRESOLUTION, static_cast<float>(1.0 / shape.spacing(1)));
    TIFFSetField(tif, TIFFTAG_SUBFILETYPE, FILETYPE_PAGE);
    TIFFSetField(tif, TIFFTAG_PAGENUMBER, static_cast<std::uint16_t>(z), static_cast<std::uint16_t>(shape.dims[2]));
    if (z == 0) TIFFSetField(tif, TIFFTAG_IMAGEDESCRIPTION, description.c_str());
    source(z * static_cast<std::int64_t>(nx) * ny, static_cast<std::int64_t>(nx) * ny, 1, slice.data());
    if (TIFFWriteEncodedStrip(tif, 0, slice.data(), static_cast<tmsize_t>(slice.size())) < 0)
      tiff_write_failed("page " + std::to_string(z) + " could not be encoded");
    if (!TIFFWriteDirectory(tif)) tiff_write_failed("page " + std::to_string(z) + " could not be written");
  }
}

void check_shape(const LabelImageShape& shape) {
  for (auto n : shape.dims)
    if (n < 1 || n > 65535) throw InvalidInputError("invalid_parameter", "TIFF label image dimensions must be 1 to 65535");
}

// Writes every page to an open TIFF and closes it, also when a page fails.
void write_and_close(TIFF* tif, const LabelImageShape& shape, const LabelRowSource& source,
                     const std::vector<std::array<std::uint8_t, 3>>& palette) {
  try {
    write_pages(tif, shape, source, palette);
  } catch (...) {
    TIFFClose(tif);
    throw;
  }
  TIFFClose(tif);
}

}  // namespace

void write_tiff_labels(const std::filesystem::path& path, const LabelImageShape& shape, const LabelRowSource& source,
                       const std::vector<std::array<std::uint8_t, 3>>& palette) {
  check_shape(shape);
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  if (!tif) throw IoError("write_failed", "cannot open " + path.string() + " for writing", {{"path", path.string()}});
  write_and_close(tif, shape, source, palette);
}

std::string tiff_labels_bytes(const LabelImageShape& shape, const LabelRowSource& source,
                              const std::vector<std::array<std::uint8_t, 3>>& palette) {
  check_shape(shape);
  MemoryOut out;
  TIFF* tif = TIFFClientOpen("class-map.tif", "w", &out, out_read, out_write, out_seek, out_close, out_size, out_map,
                             out_unmap);
  if (!tif) tiff_write_failed("cannot open an in-memory TIFF");
  write_and_close(tif, shape, source, palette);
  return std::move(out.bytes);
}

}  // namespace wish
