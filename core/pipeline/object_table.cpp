#include "core/pipeline/object_table.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "core/classify/global_descriptors.hpp"
#include "core/common/errors.hpp"

namespace wish {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

namespace {

std::string number(double v) {
  if (!std::isfinite(v)) return "";
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

std::string yes_no(const std::optional<bool>& b) { return b ? (*b ? "true" : "false") : ""; }

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void ObjectTable::add(const std::string& file, const std::string& unit, const VolumeObjectResult& r,
                      std::uint8_t value, const ClassMapLegend& legend) {
  Row row;
  row.file = file;
  row.label_id = r.object.id;
  row.object = r.object;
  row.value = value;
  row.unit = unit;
  row.genus = r.surface.genus;
  if (r.surface.genus > 0) {
    row.repair = r.surface.repaired ? r.surface.repair.method() : "none";
    row.volume_change = r.surface.repaired ? r.surface.repair.volume_change() : 0;
  }
  if (r.ok()) {
    row.area = r.surface.area;
    row.volume = r.surface.volume;
    row.voxel_volume = r.surface.voxel_volume;
  }
  if (r.ok() && r.result) {
    const PipelineResult& res = *r.result;
    row.xi.assign(res.features.invariants.data(), res.features.invariants.data() + res.features.invariants.size());
    row.global.assign(res.features.global.data(), res.features.global.data() + res.features.global.size());
    if (res.prediction) {
      const Prediction& p = *res.prediction;
      row.label = p.label;
      row.margin = p.margin;
      for (const auto& c : classes_) {
        double v = kNaN;
        for (const auto& [name, probability] : p.probabilities)
          if (name == c) v = probability;
        row.probabilities.push_back(v);
        if (c == p.label) row.probability = v;
      }
      if (p.novelty) {
        row.novel = p.novelty->novel;
        row.novelty_score = p.novelty->score;
        row.novelty_p_value = p.novelty->p_value;
      }
      row.status = value == legend.novel_value() ? "novel" : "classified";
    } else {
      row.status = "described";
    }
  } else {
    row.status = "refused";
    if (r.error) row.reason = r.error->code() + ": " + r.error->what();
  }
  rows_.push_back(std::move(row));
}

void ObjectTable::add_dropped(const std::string& file, const std::string& unit, const volume::DroppedObject& d) {
  Row row;
  row.file = file;
  row.label_id = d.object.id;
  row.object = d.object;
  row.status = "dropped";
  row.reason = std::string(volume::to_string(d.reason)) + ": " + d.why;
  row.unit = unit;
  rows_.push_back(std::move(row));
}

std::vector<std::string> ObjectTable::feature_names() const {
  std::size_t xi = 0, global = 0;
  for (const Row& r : rows_) {
    xi = std::max(xi, r.xi.size());
    global = std::max(global, r.global.size());
  }
  std::vector<std::string> names;
  for (std::size_t l = 0; l < xi; ++l) names.push_back("xi_" + std::to_string(l));
  const auto& g = global_descriptor_names();
  for (std::size_t k = 0; k < global; ++k) names.push_back("g_" + (k < g.size() ? g[k] : std::to_string(k)));
  return names;
}

std::string ObjectTable::csv() const {
  const std::vector<std::string> features = feature_names();
  std::string out =
      "file,label_id,status,reason,class,class_value,probability,margin,novel,novelty_score,novelty_p_value";
  for (const auto& c : classes_) out += ",p_" + c;
  out += ",voxel_count,centroid_x,centroid_y,centroid_z,bbox_min_x,bbox_min_y,bbox_min_z,bbox_max_x,bbox_max_y,"
         "bbox_max_z,truncated,fragments,genus_before,repair,volume_change,area,volume,voxel_volume,unit";
  for (const auto& f : features) out += "," + f;
  out += "\n";
  for (const Row& r : rows_) {
    const volume::VolumeObject& o = r.object;
    out += csv_field(r.file) + "," + std::to_string(r.label_id) + "," + r.status + "," + csv_field(r.reason) + "," +
           csv_field(r.label) + "," + std::to_string(r.value) + "," + number(r.probability) + "," + number(r.margin) + "," +
           yes_no(r.novel) + "," + number(r.novelty_score) + "," + number(r.novelty_p_value);
    for (std::size_t c = 0; c < classes_.size(); ++c)
      out += "," + (c < r.probabilities.size() ? number(r.probabilities[c]) : std::string());
    out += "," + std::to_string(o.voxel_count);
    for (int k = 0; k < 3; ++k) out += "," + number(o.centroid(k));
    for (int k = 0; k < 3; ++k) out += "," + std::to_string(o.bbox_min[static_cast<std::size_t>(k)]);
    for (int k = 0; k < 3; ++k) out += "," + std::to_string(o.bbox_max[static_cast<std::size_t>(k)]);
    out += std::string(",") + (o.truncated ? "true" : "false") + "," + std::to_string(o.fragments.size()) + "," +
           (r.status == "dropped" ? std::string() : std::to_string(r.genus)) + "," +
           (r.status == "dropped" ? std::string() : r.repair) + "," +
           (r.status == "dropped" ? std::string() : number(r.volume_change)) + "," + number(r.area) + "," +
           number(r.volume) + "," + number(r.voxel_volume) + "," + csv_field(r.unit);
    const std::size_t nxi = features.size() - (r.global.empty() ? 0 : r.global.size());
    for (std::size_t f = 0; f < features.size(); ++f) {
      double v = kNaN;
      if (f < r.xi.size()) v = r.xi[f];
      else if (!r.global.empty() && f >= nxi && f - nxi < r.global.size()) v = r.global[f - nxi];
      out += "," + number(v);
    }
    out += "\n";
  }
  return out;
}

AnnDataTable ObjectTable::anndata() const {
  AnnDataTable t;
  t.var_names = feature_names();
  using K = TableColumn::Kind;
  auto text = [&](const char* name) { return TableColumn{name, K::Text, {}, {}, {}, {}}; };
  auto num = [&](const std::string& name) { return TableColumn{name, K::Number, {}, {}, {}, {}}; };
  auto integer = [&](const char* name) { return TableColumn{name, K::Integer, {}, {}, {}, {}}; };
  std::vector<TableColumn> c = {text("file"), integer("label_id"), text("status"), text("reason"), text("class"),
                                integer("class_value"), num("probability"), num("margin"),
                                TableColumn{"novel", K::OptionalBoolean, {}, {}, {}, {}}, num("novelty_score"),
                                num("novelty_p_value")};
  const std::size_t first_p = c.size();
  for (const auto& name : classes_) c.push_back(num("p_" + name));
  const std::size_t geometry = c.size();
  for (const char* name : {"centroid_x", "centroid_y", "centroid_z"}) c.push_back(num(name));
  c.push_back(integer("voxel_count"));
  c.push_back(TableColumn{"truncated", K::Boolean, {}, {}, {}, {}});
  c.push_back(integer("fragments"));
  c.push_back(integer("genus_before"));
  c.push_back(text("repair"));
  for (const char* name : {"volume_change", "area", "volume", "voxel_volume"}) c.push_back(num(name));
  c.push_back(text("unit"));
  for (const Row& r : rows_) {
    t.obs_names.push_back(r.file + "#" + std::to_string(r.label_id));
    c[0].text.push_back(r.file);
    c[1].integer.push_back(r.label_id);
    c[2].text.push_back(r.status);
    c[3].text.push_back(r.reason);
    c[4].text.push_back(r.label);
    c[5].integer.push_back(r.value);
    c[6].number.push_back(r.probability);
    c[7].number.push_back(r.margin);
    c[8].boolean.push_back(r.novel);
    c[9].number.push_back(r.novelty_score);
    c[10].number.push_back(r.novelty_p_value);
    for (std::size_t k = 0; k < classes_.size(); ++k)
      c[first_p + k].number.push_back(k < r.probabilities.size() ? r.probabilities[k] : kNaN);
    std::size_t i = geometry;
    for (int k = 0; k < 3; ++k) c[i++].number.push_back(r.object.centroid(k));
    c[i++].integer.push_back(r.object.voxel_count);
    c[i++].boolean.push_back(r.object.truncated);
    c[i++].integer.push_back(static_cast<std::int64_t>(r.object.fragments.size()));
    c[i++].integer.push_back(r.genus);
    c[i++].text.push_back(r.status == "dropped" ? "" : r.repair);
    c[i++].number.push_back(r.status == "dropped" ? kNaN : r.volume_change);
    c[i++].number.push_back(r.area);
    c[i++].number.push_back(r.volume);
    c[i++].number.push_back(r.voxel_volume);
    c[i++].text.push_back(r.unit);
    const std::size_t nxi = t.var_names.size() - (r.global.empty() ? 0 : r.global.size());
    for (std::size_t f = 0; f < t.var_names.size(); ++f) {
      double v = kNaN;
      if (f < r.xi.size()) v = r.xi[f];
      else if (!r.global.empty() && f >= nxi && f - nxi < r.global.size()) v = r.global[f - nxi];
      t.x.push_back(v);
    }
  }
  t.obs = std::move(c);
  return t;
}

void ObjectTable::write(const std::filesystem::path& csv_path) const {
  std::ofstream out(csv_path, std::ios::binary | std::ios::trunc);
  const std::string text = csv();
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw IoError("write_failed", "cannot write " + csv_path.string(), {{"path", csv_path.string()}});
  std::filesystem::path h5ad = csv_path;
  h5ad.replace_extension(".h5ad");
  write_h5ad(h5ad, anndata());
}

}  // namespace wish
