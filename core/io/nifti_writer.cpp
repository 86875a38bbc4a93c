// NIfTI-1 single-file writer (the reader's inverse for the types it reads): little endian, vox_offset 352,
// pixdim = spacing, xyzt_units from the unit (m, mm, um; other units are written as unknown).
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include <zlib.h>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"

namespace wish {
namespace {

template <typename T>
void put(std::string& s, std::size_t offset, T v) { std::memcpy(s.data() + offset, &v, sizeof(T)); }

template <typename T>
void append(std::string& s, const volume::LabelImage& image) {
  const std::size_t start = s.size();
  s.resize(start + image.labels.size() * sizeof(T));
  for (std::size_t i = 0; i < image.labels.size(); ++i) {
    if constexpr (std::is_floating_point_v<T>) {
      if (image.probability_scale > 0) {  // a probability map: write p, not its fixed-point code
        const T p = static_cast<T>(static_cast<double>(image.labels[i]) / image.probability_scale);
        std::memcpy(s.data() + start + i * sizeof(T), &p, sizeof(T));
        continue;
      }
    }
    if (image.probability_scale > 0)
      throw InvalidInputError("invalid_parameter", "a probability map is written as float32 or float64 only");
    if (static_cast<double>(image.labels[i]) > static_cast<double>(std::numeric_limits<T>::max()))
      throw InvalidInputError("invalid_parameter", "label " + std::to_string(image.labels[i]) + " does not fit the NIfTI datatype");
    const T v = static_cast<T>(image.labels[i]);
    std::memcpy(s.data() + start + i * sizeof(T), &v, sizeof(T));
  }
}

std::string gzip_bytes(const std::string& raw) {
  z_stream zs{};
  if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw WishError(ErrorCategory::Internal, "zlib_error", "zlib could not be initialised");
  std::string out(deflateBound(&zs, static_cast<uLong>(raw.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  zs.avail_in = static_cast<uInt>(raw.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&zs, Z_FINISH);
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw WishError(ErrorCategory::Internal, "zlib_error", "gzip compression failed");
  out.resize(zs.total_out);
  return out;
}

}  // namespace

std::string write_nifti(const volume::LabelImage& image, std::string_view datatype, bool gzip) {
  for (auto n : image.dims)
    if (n < 1 || n > 32767) throw InvalidInputError("invalid_parameter", "NIfTI-1 dimensions must be 1 to 32767");
  std::string s(352, '\0');
  put<std::int32_t>(s, 0, 348);
  const std::int16_t dim[8] = {3, static_cast<std::int16_t>(image.dims[0]), static_cast<std::int16_t>(image.dims[1]),
                               static_cast<std::int16_t>(image.dims[2]), 1, 1, 1, 1};
  for (int k = 0; k < 8; ++k) put<std::int16_t>(s, 40 + 2 * k, dim[k]);
  struct Type { const char* name; std::int16_t code, bits; };
  static const Type types[] = {{"uint8", 2, 8}, {"int16", 4, 16}, {"int32", 8, 32}, {"float32", 16, 32},
                               {"float64", 64, 64}, {"uint16", 512, 16}, {"uint32", 768, 32}};
  const Type* t = nullptr;
  for (const auto& c : types)
    if (datatype == c.name) t = &c;
  if (!t) throw InvalidInputError("invalid_parameter", "unknown NIfTI datatype " + std::string(datatype));
  put<std::int16_t>(s, 70, t->code);
  put<std::int16_t>(s, 72, t->bits);
  put<float>(s, 76, 1.0f);  // qfac
  for (int k = 0; k < 3; ++k) put<float>(s, 80 + 4 * k, static_cast<float>(image.spacing(k)));
  put<float>(s, 108, 352.0f);
  put<float>(s, 112, 1.0f);
  s[123] = image.unit == "m" ? 1 : image.unit == "mm" ? 2 : image.unit == "um" ? 3 : 0;
  std::memcpy(s.data() + 344, "n+1\0", 4);
  const std::string_view dt = datatype;
  if (dt == "uint8") append<std::uint8_t>(s, image);
  else if (dt == "int16") append<std::int16_t>(s, image);
  else if (dt == "uint16") append<std::uint16_t>(s, image);
  else if (dt == "int32") append<std::int32_t>(s, image);
  else if (dt == "uint32") append<std::uint32_t>(s, image);
  else if (dt == "float32") append<float>(s, image);
  else append<double>(s, image);
  return gzip ? gzip_bytes(s) : s;
}

}  // namespace wish

// ---- Label images (core/io/label_image_writers.hpp) ----

#include "core/io/label_image_writers.hpp"

namespace wish {
namespace {

// Writes bytes to `out`, deflated into one gzip member when `gzip`.
class ByteStream {
 public:
  ByteStream(std::ostream& out, bool gzip) : out_(out), gzip_(gzip) {
    if (gzip_ && deflateInit2(&zs_, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw WishError(ErrorCategory::Internal, "zlib_error", "zlib could not be initialised");
  }
  ~ByteStream() {
    if (gzip_) deflateEnd(&zs_);
  }
  ByteStream(const ByteStream&) = delete;
  ByteStream& operator=(const ByteStream&) = delete;

  void write(const void* data, std::size_t n) { pump(data, n, Z_NO_FLUSH); }
  void finish() {
    if (gzip_) pump(nullptr, 0, Z_FINISH);
    out_.flush();
    if (!out_) throw IoError("write_failed", "the label image could not be written");
  }

 private:
  void pump(const void* data, std::size_t n, int flush) {
    if (!gzip_) {
      out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
      return;
    }
    zs_.next_in = reinterpret_cast<Bytef*>(const_cast<void*>(data));
    zs_.avail_in = static_cast<uInt>(n);
    char buf[1 << 16];
    int rc = Z_OK;
    do {
      zs_.next_out = reinterpret_cast<Bytef*>(buf);
      zs_.avail_out = sizeof buf;
      rc = deflate(&zs_, flush);
      if (rc == Z_STREAM_ERROR) throw WishError(ErrorCategory::Internal, "zlib_error", "gzip compression failed");
      out_.write(buf, static_cast<std::streamsize>(sizeof buf - zs_.avail_out));
    } while (zs_.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
  }

  std::ostream& out_;
  bool gzip_;
  z_stream zs_{};
};

}  // namespace

void write_nifti_labels(std::ostream& out, const LabelImageShape& shape, const LabelRowSource& source,
                        std::uint8_t max_value, const std::optional<NiftiGeometry>& like, bool gzip) {
  for (auto n : shape.dims)
    if (n < 1 || n > 32767) throw InvalidInputError("invalid_parameter", "NIfTI-1 dimensions must be 1 to 32767");
  std::string h(352, '\0');
  put<std::int32_t>(h, 0, 348);
  const std::int16_t dim[8] = {3, static_cast<std::int16_t>(shape.dims[0]), static_cast<std::int16_t>(shape.dims[1]),
                               static_cast<std::int16_t>(shape.dims[2]), 1, 1, 1, 1};
  for (int k = 0; k < 8; ++k) put<std::int16_t>(h, 40 + 2 * static_cast<std::size_t>(k), dim[k]);
  put<std::int16_t>(h, 68, 1002);  // intent_code NIFTI_INTENT_LABEL: the values are labels, not intensities
  put<std::int16_t>(h, 70, 2);     // datatype uint8
  put<std::int16_t>(h, 72, 8);
  put<float>(h, 108, 352.0f);
  put<float>(h, 112, 1.0f);  // scl_slope
  put<float>(h, 124, static_cast<float>(max_value));  // cal_max
  std::memcpy(h.data() + 148, "WISH class map", 14);  // descrip
  std::memcpy(h.data() + 328, "class", 5);            // intent_name
  if (like) {
    for (std::size_t k = 0; k < 8; ++k) put<float>(h, 76 + 4 * k, like->pixdim[k]);
    h[123] = static_cast<char>(like->xyzt_units);
    put<std::int16_t>(h, 252, like->qform_code);
    put<std::int16_t>(h, 254, like->sform_code);
    for (std::size_t k = 0; k < 3; ++k) {
      put<float>(h, 256 + 4 * k, like->quatern[k]);
      put<float>(h, 268 + 4 * k, like->qoffset[k]);
    }
    for (std::size_t k = 0; k < 12; ++k) put<float>(h, 280 + 4 * k, like->srow[k]);
  } else {
    put<float>(h, 76, 1.0f);  // qfac
    for (std::size_t k = 0; k < 3; ++k) put<float>(h, 80 + 4 * k, static_cast<float>(shape.spacing(static_cast<Eigen::Index>(k))));
    h[123] = shape.unit == "m" ? 1 : shape.unit == "mm" ? 2 : shape.unit == "um" ? 3 : 0;
  }
  std::memcpy(h.data() + 344, "n+1\0", 4);
  ByteStream stream(out, gzip);
  stream.write(h.data(), h.size());
  const std::int64_t slice = shape.dims[0] * shape.dims[1];
  std::vector<std::uint8_t> row(static_cast<std::size_t>(slice));
  for (std::int64_t z = 0; z < shape.dims[2]; ++z) {
    source(z * slice, slice, 1, row.data());
    stream.write(row.data(), row.size());
  }
  stream.finish();
}

}  // namespace wish
