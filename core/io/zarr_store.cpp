#include "core/io/zarr_store.hpp"

#include <cstdio>
#include <fstream>
#include <map>

#include <zip.h>

#include "core/common/errors.hpp"

namespace wish::io_detail {
namespace {

[[noreturn]] void zip_fail(const std::string& what) {
  throw InvalidInputError("parse_error", "OME-Zarr zip: " + what,
                          {{"format", std::string("ome-zarr")}, {"field", std::string("zip")}});
}

[[noreturn]] void too_big(const std::string& key, std::uint64_t size, std::uint64_t allowed) {
  throw LimitExceededError("OME-Zarr store value '" + key + "' has " + std::to_string(size) +
                               " bytes, more than the " + std::to_string(allowed) + " it can hold",
                           {{"limit", std::string("max_bytes")}, {"key", key},
                            {"value", static_cast<std::int64_t>(size)}, {"allowed", static_cast<std::int64_t>(allowed)}});
}

bool is_metadata_name(std::string_view name) {
  for (std::string_view m : {".zgroup", ".zattrs", ".zarray"})
    if (name == m || (name.size() > m.size() && name.ends_with(m) && name[name.size() - m.size() - 1] == '/')) return true;
  return false;
}

zip_t* open_zip(std::string_view bytes, std::string* why) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
  if (!source) {
    if (why) *why = zip_error_strerror(&error);
    zip_error_fini(&error);
    return nullptr;
  }
  zip_t* archive = zip_open_from_source(source, ZIP_RDONLY, &error);
  if (!archive) {
    if (why) *why = zip_error_strerror(&error);
    zip_source_free(source);
  }
  zip_error_fini(&error);
  return archive;
}

// The folder the store's keys live in: "" when a metadata entry sits at the root, else the one top-level folder that
// holds one ("cells.zarr/"). nullopt: no metadata entry at either place, or several candidate folders.
std::optional<std::string> store_prefix(zip_t* archive) {
  const zip_int64_t n = zip_get_num_entries(archive, 0);
  std::map<std::string, int> folders;
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* raw = zip_get_name(archive, static_cast<zip_uint64_t>(i), ZIP_FL_ENC_RAW);
    if (!raw) continue;
    const std::string_view name(raw);
    if (!is_metadata_name(name)) continue;
    const std::size_t slash = name.find('/');
    if (slash == std::string_view::npos) return std::string();
    if (name.find('/', slash + 1) == std::string_view::npos) ++folders[std::string(name.substr(0, slash + 1))];
  }
  if (folders.size() == 1) return folders.begin()->first;
  return std::nullopt;
}

}  // namespace

ZipZarrStore::ZipZarrStore(std::string_view bytes) {
  std::string why;
  archive_ = open_zip(bytes, &why);
  if (!archive_) zip_fail("libzip cannot open it (" + why + ")");
  const auto prefix = store_prefix(archive_);
  if (!prefix) {
    zip_discard(archive_);
    archive_ = nullptr;
    zip_fail("no zarr metadata (.zgroup, .zattrs or .zarray) at the zip's root or in one top-level folder");
  }
  prefix_ = *prefix;
}

ZipZarrStore::~ZipZarrStore() {
  if (archive_) zip_discard(archive_);
}

std::optional<std::string> ZipZarrStore::get(const std::string& key, std::uint64_t max_bytes) const {
  const std::string name = prefix_ + key;
  const zip_int64_t index = zip_name_locate(archive_, name.c_str(), ZIP_FL_ENC_RAW);
  if (index < 0) return std::nullopt;
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat_index(archive_, static_cast<zip_uint64_t>(index), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    zip_fail("entry '" + name + "' has no size");
  if (st.size > max_bytes) too_big(key, st.size, max_bytes);
  zip_file_t* file = zip_fopen_index(archive_, static_cast<zip_uint64_t>(index), 0);
  if (!file) zip_fail("entry '" + name + "' cannot be opened (" + std::string(zip_strerror(archive_)) + ")");
  std::string value(static_cast<std::size_t>(st.size), '\0');
  std::size_t got = 0;
  while (got < value.size()) {
    const zip_int64_t r = zip_fread(file, value.data() + got, value.size() - got);
    if (r <= 0) break;
    got += static_cast<std::size_t>(r);
  }
  // Reading one byte past the stated size tells a truthful entry from one whose data is longer than its header says.
  char extra = 0;
  const bool longer = got == value.size() && zip_fread(file, &extra, 1) > 0;
  const std::string why = zip_file_strerror(file);
  zip_fclose(file);
  if (got != value.size() || longer)
    zip_fail("entry '" + name + "' is corrupt: " + std::to_string(got) + " of " + std::to_string(st.size) +
             " bytes read (" + why + ")");
  return value;
}

std::optional<std::string> DirectoryZarrStore::get(const std::string& key, std::uint64_t max_bytes) const {
  const std::filesystem::path path = root_ / key;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return std::nullopt;
  if (size > max_bytes) too_big(key, size, max_bytes);
  std::ifstream in(path, std::ios::binary);
  std::string value(static_cast<std::size_t>(size), '\0');
  if (!in.read(value.data(), static_cast<std::streamsize>(size)))
    throw IoError("file_not_found", "cannot read " + path.string(), {{"path", path.string()}});
  return value;
}

bool is_zarr_zip(std::string_view bytes) {
  if (bytes.size() < 4 || bytes.substr(0, 4) != std::string_view("PK\x03\x04", 4)) return false;
  zip_t* archive = open_zip(bytes, nullptr);
  if (!archive) return false;
  const bool ok = store_prefix(archive).has_value();
  zip_discard(archive);
  return ok;
}

std::string write_zip(const std::vector<std::pair<std::string, std::string>>& entries) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* buffer = zip_source_buffer_create(nullptr, 0, 0, &error);
  if (!buffer) throw std::runtime_error("libzip: " + std::string(zip_error_strerror(&error)));
  zip_source_keep(buffer);  // zip_close would free it; its bytes are the result
  zip_t* archive = zip_open_from_source(buffer, ZIP_TRUNCATE, &error);
  if (!archive) {
    zip_source_free(buffer);
    throw std::runtime_error("libzip: " + std::string(zip_error_strerror(&error)));
  }
  auto fail = [&](const std::string& what) {
    const std::string message = "libzip: " + what + " (" + zip_strerror(archive) + ")";
    zip_discard(archive);
    zip_source_free(buffer);
    throw std::runtime_error(message);
  };
  for (const auto& [name, value] : entries) {
    zip_source_t* s = zip_source_buffer(archive, value.data(), value.size(), 0);  // read at zip_close: `entries` lives
    if (!s) fail("cannot add '" + name + "'");
    const zip_int64_t index = zip_file_add(archive, name.c_str(), s, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE);
    if (index < 0) {
      zip_source_free(s);
      fail("cannot add '" + name + "'");
    }
    zip_set_file_compression(archive, static_cast<zip_uint64_t>(index), ZIP_CM_STORE, 0);
  }
  if (zip_close(archive) != 0) fail("cannot write the zip");
  std::string out;
  if (zip_source_open(buffer) == 0) {
    zip_source_seek(buffer, 0, SEEK_END);
    const zip_int64_t size = zip_source_tell(buffer);
    zip_source_seek(buffer, 0, SEEK_SET);
    if (size > 0) {
      out.resize(static_cast<std::size_t>(size));
      const zip_int64_t r = zip_source_read(buffer, out.data(), static_cast<zip_uint64_t>(size));
      out.resize(r > 0 ? static_cast<std::size_t>(r) : 0);
    }
    zip_source_close(buffer);
  }
  zip_source_free(buffer);
  zip_error_fini(&error);
  return out;
}

}  // namespace wish::io_detail
