#pragma once
// Internal to core/io: the zarr v2 chunk compressors a label image is stored with, decoded through Debian's
// libraries: "zlib" and "gzip" (zlib), "zstd" (libzstd), "blosc" (libblosc, any of its inner codecs and shuffles).
// A chunk always decodes to exactly the chunk's size in bytes (zarr stores edge chunks whole); any other size, and any
// decoder error, is a parse_error naming the chunk. Output is never allowed to grow past that size, so a hostile
// chunk cannot make the reader allocate more than the chunk the metadata announced (and the limits allowed).

#include <cstddef>
#include <string>
#include <string_view>

namespace wish::io_detail {

enum class ZarrCompressor { None, Zlib, Gzip, Zstd, Blosc };

// "zlib" -> Zlib, ...; false for an id this reader does not decode.
bool zarr_compressor_from_id(std::string_view id, ZarrCompressor& out);
const char* zarr_compressor_list();  // "zlib, gzip, zstd, blosc" for messages

// Decodes `encoded` into `out` (resized to `expected_bytes`). `key` names the chunk in errors.
void decode_zarr_chunk(ZarrCompressor compressor, std::string_view encoded, std::size_t expected_bytes,
                       const std::string& key, std::string& out);

}  // namespace wish::io_detail
