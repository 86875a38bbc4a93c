#include "core/io/zarr_codecs.hpp"

#include <algorithm>
#include <cstring>

#include <blosc.h>
#include <zlib.h>
#include <zstd.h>

#include "core/common/errors.hpp"

namespace wish::io_detail {
namespace {

[[noreturn]] void bad_chunk(const std::string& key, const std::string& why) {
  throw InvalidInputError("parse_error", "OME-Zarr chunk '" + key + "' cannot be decoded: " + why,
                          {{"format", std::string("ome-zarr")}, {"field", std::string("chunk")}, {"key", key}});
}

std::string size_mismatch(std::size_t got, std::size_t expected) {
  return "it holds " + std::to_string(got) + " bytes, the chunk shape and dtype need " + std::to_string(expected);
}

// zlib streams (window bits 15) and gzip members (15 + 16), inflated into at most `out.size()` bytes.
void inflate_into(std::string_view in, int window_bits, const std::string& key, std::string& out) {
  z_stream zs{};
  if (inflateInit2(&zs, window_bits) != Z_OK) bad_chunk(key, "zlib could not be initialised");
  std::size_t consumed = 0, produced = 0;
  int rc = Z_OK;
  char spare[1];
  bool overflow = false;
  while (true) {
    const std::size_t in_chunk = std::min<std::size_t>(in.size() - consumed, 1u << 30);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data() + consumed));
    zs.avail_in = static_cast<uInt>(in_chunk);
    // Past the expected size, one spare byte: a stream that fills it holds more than the chunk.
    const bool full = produced == out.size();
    char* dest = full ? spare : out.data() + produced;
    const std::size_t out_chunk = full ? 1 : std::min<std::size_t>(out.size() - produced, 1u << 30);
    zs.next_out = reinterpret_cast<Bytef*>(dest);
    zs.avail_out = static_cast<uInt>(out_chunk);
    rc = inflate(&zs, Z_NO_FLUSH);
    consumed += in_chunk - zs.avail_in;
    const std::size_t made = out_chunk - zs.avail_out;
    if (full && made > 0) { overflow = true; break; }
    produced += full ? 0 : made;
    if (rc == Z_STREAM_END) break;
    if (rc != Z_OK && rc != Z_BUF_ERROR) break;
    if (rc == Z_BUF_ERROR && consumed >= in.size()) break;  // input ended before the stream did
  }
  const std::string why = zs.msg ? zs.msg : "";
  inflateEnd(&zs);
  if (overflow) bad_chunk(key, "it inflates to more than the " + std::to_string(out.size()) + " bytes of a chunk");
  if (rc != Z_STREAM_END)
    bad_chunk(key, "the " + std::string(window_bits > 15 ? "gzip" : "zlib") + " stream is corrupt or truncated" +
                       (why.empty() ? "" : " (" + why + ")"));
  if (produced != out.size()) bad_chunk(key, size_mismatch(produced, out.size()));
}

void zstd_into(std::string_view in, const std::string& key, std::string& out) {
  const unsigned long long size = ZSTD_getFrameContentSize(in.data(), in.size());
  if (size == ZSTD_CONTENTSIZE_ERROR) bad_chunk(key, "not a zstd frame");
  if (size != ZSTD_CONTENTSIZE_UNKNOWN && size != out.size()) bad_chunk(key, size_mismatch(static_cast<std::size_t>(size), out.size()));
  // ZSTD_decompress never writes past the capacity; one byte more tells an oversized stream from an exact one.
  std::string buffer(out.size() + 1, '\0');
  const std::size_t r = ZSTD_decompress(buffer.data(), buffer.size(), in.data(), in.size());
  if (ZSTD_isError(r)) bad_chunk(key, std::string("zstd: ") + ZSTD_getErrorName(r));
  if (r != out.size()) bad_chunk(key, size_mismatch(r, out.size()));
  std::memcpy(out.data(), buffer.data(), out.size());
}

void blosc_into(std::string_view in, const std::string& key, std::string& out) {
  std::size_t nbytes = 0;
  // blosc_decompress trusts the sizes in the chunk's own header; validate them against the buffer first.
  if (blosc_cbuffer_validate(in.data(), in.size(), &nbytes) != 0) bad_chunk(key, "not a valid blosc buffer");
  if (nbytes != out.size()) bad_chunk(key, size_mismatch(nbytes, out.size()));
  if (out.empty()) return;
  // The _ctx form keeps no global state (the service reads volumes on several threads); one internal thread.
  const int r = blosc_decompress_ctx(in.data(), out.data(), out.size(), 1);
  if (r < 0 || static_cast<std::size_t>(r) != out.size())
    bad_chunk(key, "blosc reported error " + std::to_string(r) + " (an inner codec this libblosc lacks, or corrupt data)");
}

}  // namespace

bool zarr_compressor_from_id(std::string_view id, ZarrCompressor& out) {
  if (id == "zlib") out = ZarrCompressor::Zlib;
  else if (id == "gzip") out = ZarrCompressor::Gzip;
  else if (id == "zstd") out = ZarrCompressor::Zstd;
  else if (id == "blosc") out = ZarrCompressor::Blosc;
  else return false;
  return true;
}

const char* zarr_compressor_list() { return "zlib, gzip, zstd, blosc (or none)"; }

void decode_zarr_chunk(ZarrCompressor compressor, std::string_view encoded, std::size_t expected_bytes,
                       const std::string& key, std::string& out) {
  out.assign(expected_bytes, '\0');
  switch (compressor) {
    case ZarrCompressor::None:
      if (encoded.size() != expected_bytes) bad_chunk(key, size_mismatch(encoded.size(), expected_bytes));
      if (expected_bytes) std::memcpy(out.data(), encoded.data(), expected_bytes);
      return;
    case ZarrCompressor::Zlib: inflate_into(encoded, 15, key, out); return;
    case ZarrCompressor::Gzip: inflate_into(encoded, 15 + 16, key, out); return;
    case ZarrCompressor::Zstd: zstd_into(encoded, key, out); return;
    case ZarrCompressor::Blosc: blosc_into(encoded, key, out); return;
  }
}

}  // namespace wish::io_detail
