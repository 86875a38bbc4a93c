// AnnData (.h5ad) through libhdf5's C API (core/io/h5ad_writer.hpp). Each HDF5 handle is closed by a small owner
// so that an error part-way leaves no handle open; any negative return is a write_failed naming the element.
#include "core/io/h5ad_writer.hpp"

#include <hdf5.h>

#include "core/common/errors.hpp"

namespace wish {
namespace {

[[noreturn]] void failed(const std::string& what) { throw IoError("write_failed", "AnnData table: cannot write " + what); }

// An hid_t closed by `close` when it goes out of scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) failed(what);
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

Handle utf8_string_type() {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose, "a string type");
  if (H5Tset_size(t, H5T_VARIABLE) < 0 || H5Tset_cset(t, H5T_CSET_UTF8) < 0) failed("a string type");
  return Handle(H5Tcopy(t), H5Tclose, "a string type");
}

void string_attribute(hid_t owner, const char* name, const std::string& value) {
  const Handle type = utf8_string_type();
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose, "an attribute");
  const Handle attr(H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, std::string("attribute ") + name);
  const char* p = value.c_str();
  if (H5Awrite(attr, type, &p) < 0) failed(std::string("attribute ") + name);
}

void string_array_attribute(hid_t owner, const char* name, const std::vector<std::string>& values) {
  const Handle type = utf8_string_type();
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "an attribute");
  const Handle attr(H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, std::string("attribute ") + name);
  std::vector<const char*> p;
  for (const auto& v : values) p.push_back(v.c_str());
  if (n > 0 && H5Awrite(attr, type, p.data()) < 0) failed(std::string("attribute ") + name);
}

// numpy's bool as h5py stores it: an 8-bit enum {FALSE = 0, TRUE = 1} (read back as numpy.bool_).
Handle bool_type() {
  Handle type(H5Tenum_create(H5T_NATIVE_INT8), H5Tclose, "a bool type");
  const std::int8_t f = 0, t = 1;
  if (H5Tenum_insert(type, "FALSE", &f) < 0 || H5Tenum_insert(type, "TRUE", &t) < 0) failed("a bool type");
  return Handle(H5Tcopy(type), H5Tclose, "a bool type");
}

void bool_attribute(hid_t owner, const char* name, bool value) {
  const Handle type = bool_type();
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose, "an attribute");
  const Handle attr(H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, name);
  const std::int8_t v = value ? 1 : 0;
  if (H5Awrite(attr, type, &v) < 0) failed(name);
}

void encoding(hid_t owner, const char* type, const char* version) {
  string_attribute(owner, "encoding-type", type);
  string_attribute(owner, "encoding-version", version);
}

Handle group(hid_t parent, const std::string& name) {
  return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "group " + name);
}

void string_dataset(hid_t parent, const std::string& name, const std::vector<std::string>& values) {
  const Handle type = utf8_string_type();
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, name);
  const Handle set(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, name);
  std::vector<const char*> p;
  for (const auto& v : values) p.push_back(v.c_str());
  if (n > 0 && H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()) < 0) failed(name);
  encoding(set, "string-array", "0.2.0");
}

template <class T>
void numeric_dataset(hid_t parent, const std::string& name, hid_t type, const std::vector<T>& values,
                     std::vector<hsize_t> dims) {
  const Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, name);
  const Handle set(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose, name);
  if (!values.empty() && H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) failed(name);
  encoding(set, "array", "0.2.0");
}

void bool_dataset(hid_t parent, const std::string& name, const std::vector<std::optional<bool>>& values) {
  const Handle type = bool_type();
  std::vector<std::int8_t> v;
  for (const auto& b : values) v.push_back(b.value_or(false) ? 1 : 0);
  numeric_dataset(parent, name, type, v, {values.size()});
}

// AnnData's categorical: codes (int8, -1 missing) into categories "false", "true".
void optional_bool_categorical(hid_t parent, const std::string& name, const std::vector<std::optional<bool>>& values) {
  const Handle g = group(parent, name);
  encoding(g, "categorical", "0.2.0");
  bool_attribute(g, "ordered", false);
  string_dataset(g, "categories", {"false", "true"});
  std::vector<std::int8_t> codes;
  for (const auto& b : values) codes.push_back(b ? (*b ? 1 : 0) : -1);
  numeric_dataset(g, "codes", H5T_NATIVE_INT8, codes, {values.size()});
}

void empty_dict(hid_t parent, const char* name) {
  const Handle g = group(parent, name);
  encoding(g, "dict", "0.1.0");
}

void dataframe(hid_t parent, const char* name, const std::vector<std::string>& index, const std::vector<TableColumn>& columns) {
  const Handle g = group(parent, name);
  encoding(g, "dataframe", "0.2.0");
  string_attribute(g, "_index", "_index");
  std::vector<std::string> order;
  for (const auto& c : columns) order.push_back(c.name);
  string_array_attribute(g, "column-order", order);
  string_dataset(g, "_index", index);
  for (const TableColumn& c : columns) {
    switch (c.kind) {
      case TableColumn::Kind::Text: string_dataset(g, c.name, c.text); break;
      case TableColumn::Kind::Number: numeric_dataset(g, c.name, H5T_NATIVE_DOUBLE, c.number, {c.number.size()}); break;
      case TableColumn::Kind::Integer: numeric_dataset(g, c.name, H5T_NATIVE_INT64, c.integer, {c.integer.size()}); break;
      case TableColumn::Kind::Boolean: bool_dataset(g, c.name, c.boolean); break;
      case TableColumn::Kind::OptionalBoolean: optional_bool_categorical(g, c.name, c.boolean); break;
    }
  }
}

std::size_t column_size(const TableColumn& c) {
  switch (c.kind) {
    case TableColumn::Kind::Text: return c.text.size();
    case TableColumn::Kind::Number: return c.number.size();
    case TableColumn::Kind::Integer: return c.integer.size();
    default: return c.boolean.size();
  }
}

}  // namespace

void write_h5ad(const std::filesystem::path& path, const AnnDataTable& table) {
  const std::size_t n = table.obs_names.size();
  for (const TableColumn& c : table.obs)
    if (column_size(c) != n)
      throw InvalidInputError("invalid_parameter", "AnnData column '" + c.name + "' has " + std::to_string(column_size(c)) +
                                                       " values for " + std::to_string(n) + " observations");
  if (table.x.size() != n * table.var_names.size())
    throw InvalidInputError("invalid_parameter", "AnnData X holds " + std::to_string(table.x.size()) + " values for " +
                                                     std::to_string(n) + " x " + std::to_string(table.var_names.size()));
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are returned and reported here, not printed by libhdf5
  const Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path.string());
  encoding(file, "anndata", "0.1.0");
  numeric_dataset(file, "X", H5T_NATIVE_DOUBLE, table.x, {n, table.var_names.size()});
  dataframe(file, "obs", table.obs_names, table.obs);
  dataframe(file, "var", table.var_names, {});
  for (const char* name : {"uns", "obsm", "varm", "obsp", "varp", "layers"}) empty_dict(file, name);
}

}  // namespace wish
