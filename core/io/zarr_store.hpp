#pragma once
// Internal to core/io: a zarr v2 store seen as keys -> bytes ("labels/.zattrs", "labels/cells/0/0.0.0"), either a
// directory on disk or a zip in memory (zarr's ZipStore layout: the keys are the zip's entry names, read through
// libzip). A zip whose keys all sit under one top-level folder ("cells.zarr/.zattrs", as `zip -r` makes it) is read
// from that folder. Every value is size-checked against the caller's bound before it is read.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

struct zip;

namespace wish::io_detail {

class ZarrStore {
 public:
  virtual ~ZarrStore() = default;
  // The value under `key`, or nullopt when the store has none. A value of more than `max_bytes` is refused
  // (LimitExceededError naming the key) before it is read.
  virtual std::optional<std::string> get(const std::string& key, std::uint64_t max_bytes) const = 0;
};

class ZipZarrStore final : public ZarrStore {
 public:
  // `bytes` must outlive the store. Throws parse_error when libzip cannot open the zip.
  explicit ZipZarrStore(std::string_view bytes);
  ~ZipZarrStore() override;
  ZipZarrStore(const ZipZarrStore&) = delete;
  ZipZarrStore& operator=(const ZipZarrStore&) = delete;
  std::optional<std::string> get(const std::string& key, std::uint64_t max_bytes) const override;

 private:
  ::zip* archive_ = nullptr;
  std::string prefix_;  // "" or "folder/" when every key sits under one top-level folder
};

class DirectoryZarrStore final : public ZarrStore {
 public:
  explicit DirectoryZarrStore(std::filesystem::path root) : root_(std::move(root)) {}
  std::optional<std::string> get(const std::string& key, std::uint64_t max_bytes) const override;

 private:
  std::filesystem::path root_;
};

// True for a zip (local file header "PK\3\4") that libzip opens and that holds a zarr metadata entry (.zgroup,
// .zattrs or .zarray) at its root or under one top-level folder.
bool is_zarr_zip(std::string_view bytes);

// A zip (entries stored, not recompressed) of (key, value) pairs: a ZipStore as zarr writes it.
std::string write_zip(const std::vector<std::pair<std::string, std::string>>& entries);

}  // namespace wish::io_detail
