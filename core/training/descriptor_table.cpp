#include "core/training/descriptor_table.hpp"

#include <cstdlib>
#include <sstream>

#include "core/classify/global_descriptors.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_canonical_frame.hpp"
#include "core/common/errors.hpp"

namespace wish {
namespace {

[[noreturn]] void bad(const std::string& message) { throw InvalidInputError("invalid_descriptor_csv", message); }

std::string quote(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

double to_double(const std::string& s, std::size_t line, const std::string& column) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) bad("line " + std::to_string(line) + ": column " + column + " is not a number ('" + s + "')");
  return v;
}

}  // namespace

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') { cell += '"'; ++i; }
      else if (c == '"') quoted = false;
      else cell += c;
    } else if (c == '"') { quoted = true; any = true; }
    else if (c == ',') { row.push_back(cell); cell.clear(); any = true; }
    else if (c == '\n' || c == '\r') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      if (any || !cell.empty()) { row.push_back(cell); rows.push_back(row); }
      row.clear(); cell.clear(); any = false;
    } else { cell += c; any = true; }
  }
  if (quoted) bad("unterminated quoted field at the end of the CSV");
  if (any || !cell.empty()) { row.push_back(cell); rows.push_back(row); }
  return rows;
}

std::vector<std::pair<std::string, std::string>> read_manifest(const std::string& csv_text, const std::filesystem::path& base) {
  auto rows = parse_csv(csv_text);
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() < 2) bad("manifest line " + std::to_string(i + 1) + ": expected path,label");
    if (i == 0 && (rows[i][0] == "path" || rows[i][0] == "file")) continue;  // header
    std::filesystem::path p = rows[i][0];
    if (p.is_relative()) p = base / p;
    out.emplace_back(p.lexically_normal().string(), rows[i][1]);
  }
  return out;
}

namespace {

DescriptorTable read_table(const std::string& csv_text, const std::map<std::string, std::string>& labels,
                           bool keep_unlabelled) {
  const auto rows = parse_csv(csv_text);
  if (rows.empty()) bad("the descriptor CSV is empty");
  const auto& header = rows[0];
  int file_col = -1, label_col = -1, label_id_col = -1;
  std::map<int, int> xi_col;  // l -> column
  std::map<std::string, int> g_col, csh_col;
  std::map<int, int> lb_col;  // i -> column
  for (int c = 0; c < static_cast<int>(header.size()); ++c) {
    const std::string& h = header[c];
    if (h == "file" || h == "path") file_col = c;
    else if (h == "label" || h == "class") label_col = c;
    else if (h == "label_id") label_id_col = c;
    else if (h.rfind("xi_", 0) == 0) xi_col[std::atoi(h.c_str() + 3)] = c;
    else if (h.rfind("g_", 0) == 0) g_col[h.substr(2)] = c;
    else if (h.rfind("lb_", 0) == 0) lb_col[std::atoi(h.c_str() + 3)] = c;
    else if (h.rfind("csh_", 0) == 0) csh_col[h] = c;
  }
  if (file_col < 0) bad("the descriptor CSV has no 'file' column");
  if (xi_col.empty()) bad("the descriptor CSV has no xi_<l> columns");
  DescriptorTable t;
  t.lmax = xi_col.rbegin()->first;
  for (int l = 0; l <= t.lmax; ++l)
    if (!xi_col.count(l)) bad("the descriptor CSV lacks column xi_" + std::to_string(l));
  t.has_global = true;
  for (const auto& name : global_descriptor_names()) t.has_global = t.has_global && g_col.count(name);
  // The spectrum lb_1..lb_n and the canonical coefficients of degrees 1..L: complete blocks or none.
  const int n_lb = lb_col.empty() ? 0 : lb_col.rbegin()->first;
  for (int i = 1; i <= n_lb; ++i)
    if (!lb_col.count(i)) bad("the descriptor CSV lacks column lb_" + std::to_string(i));
  std::vector<int> csh_order;
  if (!csh_col.empty()) {
    int L = 1;
    while (3 * (sh_count(L) - 1) < static_cast<int>(csh_col.size())) ++L;
    for (const auto& name : canonical_sh_feature_names(1, L)) {
      const auto it = csh_col.find(name);
      if (it == csh_col.end()) bad("the descriptor CSV lacks column " + name + " of the canonical SH coefficients");
      csh_order.push_back(it->second);
    }
  }
  if (label_col < 0 && labels.empty() && !keep_unlabelled) bad("the descriptor CSV has no 'label' column; pass a labels manifest (path,label)");
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& r = rows[i];
    if (r.size() != header.size())
      bad("line " + std::to_string(i + 1) + " has " + std::to_string(r.size()) + " fields, the header " + std::to_string(header.size()));
    TrainingSample s;
    s.id = r[file_col];
    if (label_id_col >= 0 && !r[label_id_col].empty()) s.id += "#" + r[label_id_col];  // an object of a label volume
    if (label_col >= 0) s.label = r[label_col];
    if (s.label.empty()) {
      auto it = labels.find(s.id);
      if (it == labels.end()) {  // join on the file name when paths differ
        const std::string name = std::filesystem::path(s.id).filename().string();
        for (const auto& [path, label] : labels)
          if (std::filesystem::path(path).filename().string() == name) { it = labels.find(path); break; }
      }
      if (it != labels.end()) s.label = it->second;
    }
    if (s.label.empty() && !keep_unlabelled) {
      t.unlabelled.push_back(s.id);
      continue;
    }
    s.features.invariants.resize(t.lmax + 1);
    for (int l = 0; l <= t.lmax; ++l) s.features.invariants(l) = to_double(r[xi_col[l]], i + 1, "xi_" + std::to_string(l));
    if (t.has_global) {
      s.features.global.resize(kGlobalCount);
      for (int g = 0; g < kGlobalCount; ++g)
        s.features.global(g) = to_double(r[g_col[global_descriptor_names()[g]]], i + 1, "g_" + global_descriptor_names()[g]);
    }
    s.features.laplace_spectrum.resize(n_lb);
    for (int k = 1; k <= n_lb; ++k) s.features.laplace_spectrum(k - 1) = to_double(r[lb_col[k]], i + 1, "lb_" + std::to_string(k));
    s.features.canonical_sh.resize(static_cast<Eigen::Index>(csh_order.size()));
    for (std::size_t k = 0; k < csh_order.size(); ++k)
      s.features.canonical_sh(static_cast<Eigen::Index>(k)) = to_double(r[csh_order[k]], i + 1, header[csh_order[k]]);
    t.samples.push_back(std::move(s));
  }
  return t;
}

}  // namespace

DescriptorTable read_descriptor_table(const std::string& csv_text, const std::map<std::string, std::string>& labels) {
  return read_table(csv_text, labels, false);
}

DescriptorTable read_unlabelled_descriptor_table(const std::string& csv_text) { return read_table(csv_text, {}, true); }

std::string write_descriptor_table(const std::vector<TrainingSample>& samples) {
  std::ostringstream o;
  o << "file,label";
  const int lmax = samples.empty() ? -1 : static_cast<int>(samples[0].features.invariants.size()) - 1;
  const bool global = !samples.empty() && samples[0].features.global.size() == kGlobalCount;
  for (int l = 0; l <= lmax; ++l) o << ",xi_" << l;
  if (global)
    for (const auto& name : global_descriptor_names()) o << ",g_" << name;
  // The spectrum and the canonical coefficients when they were computed (families that use them).
  const Eigen::Index n_lb = samples.empty() ? 0 : samples[0].features.laplace_spectrum.size();
  const Eigen::Index n_csh = samples.empty() ? 0 : samples[0].features.canonical_sh.size();
  for (Eigen::Index i = 1; i <= n_lb; ++i) o << ",lb_" << i;
  if (n_csh > 0)
    for (const auto& name : canonical_sh_feature_names(1, sh_lmax_from_count(n_csh / 3 + 1))) o << "," << name;
  o << "\n";
  o.precision(17);
  for (const auto& s : samples) {
    o << quote(s.id) << "," << quote(s.label);
    for (int l = 0; l <= lmax; ++l) o << "," << s.features.invariants(l);
    if (global)
      for (int g = 0; g < kGlobalCount; ++g) o << "," << s.features.global(g);
    for (Eigen::Index i = 0; i < n_lb; ++i) o << "," << s.features.laplace_spectrum(i);
    for (Eigen::Index i = 0; i < n_csh; ++i) o << "," << s.features.canonical_sh(i);
    o << "\n";
  }
  return o.str();
}

}  // namespace wish
