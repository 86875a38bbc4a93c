#pragma once
// A table written as AnnData (.h5ad), the format single-cell analysts load with one call (anndata.read_h5ad in
// Python, zellkonverter / anndata in R), through Debian's libhdf5 (C API). The layout is AnnData's on-disk format
// (encoding-type "anndata", version 0.1.0; anndata >= 0.8 reads it):
//   X      float64 [n_obs, n_vars], the features (NaN where an observation has none)
//   obs    dataframe (0.2.0): _index = the observation names, one dataset per column in column-order: numbers as
//          float64 / int64 arrays, text as UTF-8 string arrays, yes/no as booleans, and yes/no/unknown as a
//          categorical (categories "false", "true"; code -1 for unknown)
//   var    dataframe: _index = the feature names, no columns
//   uns, obsm, varm, obsp, varp, layers: empty
// Every string is variable-length UTF-8, the form h5py (and so anndata) decodes to str.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace wish {

struct TableColumn {
  enum class Kind { Text, Number, Integer, Boolean, OptionalBoolean };
  std::string name;
  Kind kind = Kind::Number;
  std::vector<std::string> text;
  std::vector<double> number;
  std::vector<std::int64_t> integer;
  std::vector<std::optional<bool>> boolean;  // Boolean: every value set; OptionalBoolean: unset = unknown
};

struct AnnDataTable {
  std::vector<std::string> obs_names;  // unique
  std::vector<TableColumn> obs;        // each column one value per observation
  std::vector<std::string> var_names;  // the features
  std::vector<double> x;               // n_obs × n_vars, row-major
};

// Throws IoError("write_failed") when the file cannot be written, InvalidInputError("invalid_parameter") when a
// column's length or X's size does not match the observations.
void write_h5ad(const std::filesystem::path& path, const AnnDataTable& table);

}  // namespace wish
