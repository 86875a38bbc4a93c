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
