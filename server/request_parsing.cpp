#include "server/request_parsing.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <set>

#include "core/classify/feature_pipeline.hpp"  // kMinFeatureLmax
#include "core/common/errors.hpp"
#include "core/sh/sh_lmax_range.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/volume/object_mode.hpp"

namespace wish::server {

namespace {

[[noreturn]] void invalid_parameter(const std::string& name, const std::string& message, const std::string& value) {
  throw InvalidInputError("invalid_parameter", message, {{"parameter", name}, {"value", value}});
}

int parse_int(const std::string& name, const std::string& value, int lo, int hi) {
  int out = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(value.data(), end, out);
  if (value.empty() || ec != std::errc() || ptr != end)
    invalid_parameter(name, "parameter " + name + "='" + value + "' is not an integer", value);
  if (out < lo || out > hi)
    invalid_parameter(name, "parameter " + name + "=" + value + " is outside " + std::to_string(lo) + ".." +
                            std::to_string(hi), value);
  return out;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

std::vector<std::string> split_commas(const std::string& value) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = value.find(',', start);
    out.push_back(trim(value.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

double parse_positive(const std::string& name, const std::string& item, const std::string& value) {
  double out = 0;
  const char* end = item.data() + item.size();
  const auto [ptr, ec] = std::from_chars(item.data(), end, out);
  if (item.empty() || ec != std::errc() || ptr != end || !std::isfinite(out) || out <= 0)
    invalid_parameter(name, "parameter " + name + "='" + value + "': '" + item + "' is not a positive number", value);
  return out;
}

double parse_non_negative(const std::string& name, const std::string& value) {
  double out = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(value.data(), end, out);
  if (value.empty() || ec != std::errc() || ptr != end || !std::isfinite(out) || out < 0)
    invalid_parameter(name, "parameter " + name + "='" + value + "' is not a number >= 0", value);
  return out;
}

// The volume parameters (core/pipeline/volume_overrides.hpp); false when `name` is not one.
bool parse_volume_param(const std::string& name, const std::string& value, VolumeOverrides& out,
                        std::vector<std::string>& given) {
  if (name == "spacing") {
    const auto items = split_commas(value);
    if (items.size() != 3)
      invalid_parameter(name, "parameter spacing='" + value + "' must be three voxel sizes x,y,z", value);
    out.spacing = std::array<double, 3>{parse_positive(name, items[0], value), parse_positive(name, items[1], value),
                                        parse_positive(name, items[2], value)};
  } else if (name == "unit") {
    const bool plain = !value.empty() && value.size() <= 16 &&
                       std::all_of(value.begin(), value.end(), [](unsigned char c) { return std::isalpha(c) || c == '_'; });
    if (!plain) invalid_parameter(name, "parameter unit='" + value + "' must be a unit name such as nm or um", value);
    out.unit = value;
  } else if (name == "objects") {
    // The one list of modes (core kObjectModeNames; proto/openapi.json's ObjectMode schema is generated from it).
    const auto mode = volume::kObjectModeNames.find(lower(value));
    if (!mode)
      invalid_parameter(name, "objects must be " + volume::kObjectModeNames.expected() + ", not '" + value + "'", value);
    out.objects = *mode;
  } else if (name == "min_voxels") {
    out.min_voxels = parse_int(name, value, 0, 2'000'000'000);
  } else if (name == "fragment_gap") {
    out.fragment_gap = parse_int(name, value, -1, 64);
  } else if (name == "max_repair_share") {
    out.max_repair_share = parse_non_negative(name, value);
  } else if (name == "drop_truncated") {
    const std::string b = lower(value);
    if (b == "true" || b == "1" || b == "yes") out.drop_truncated = true;
    else if (b == "false" || b == "0" || b == "no") out.drop_truncated = false;
    else invalid_parameter(name, "drop_truncated must be true or false, not '" + value + "'", value);
  } else if (name == "threshold") {
    out.threshold = parse_positive(name, value, value);
  } else if (name == "label_image") {
    const bool plain = !value.empty() && value.size() <= 255 && value.find('/') == std::string::npos &&
                       std::all_of(value.begin(), value.end(), [](unsigned char c) { return c > 32 && c < 127; });
    if (!plain) invalid_parameter(name, "parameter label_image='" + value + "' must name one label image (labels/NAME)", value);
    out.label_image = value;
  } else if (name == "level") {
    out.level = static_cast<int>(parse_int(name, value, 0, 64));
  } else if (name == "labels") {
    for (const auto& item : split_commas(value)) {
      std::uint32_t id = 0;
      const char* end = item.data() + item.size();
      const auto [ptr, ec] = std::from_chars(item.data(), end, id);
      if (item.empty() || ec != std::errc() || ptr != end || id == 0)
        invalid_parameter(name, "parameter labels='" + value + "': '" + item + "' is not a label id (1..4294967295)", value);
      out.label_ids.push_back(id);
    }
  } else {
    return false;
  }
  given.push_back(name);
  return true;
}

}  // namespace

ComputeParams parse_compute_params(Operation op, const ParamMap& params, const ServerConfig& config) {
  static const std::set<std::string> known_describe{"lmax", "method", "steps", "include", "reconstruction_level",
                                                    "format", "spacing", "unit", "objects", "min_voxels",
                                                    "drop_truncated", "labels", "threshold", "label_image", "level",
                                                    "fragment_gap", "max_repair_share", "output"};
  ComputeParams out;
  std::set<std::string> seen;
  for (const auto& [name, raw] : params) {
    const std::string value = trim(raw);
    const bool known = known_describe.count(name) || (op == Operation::Classify && name == "model");
    if (!known)
      throw InvalidInputError("invalid_parameter", "unknown parameter '" + name + "'" +
                                                   (name == "model" ? " (only /v1/classify takes a model)" : ""),
                              {{"parameter", name}});
    if (!seen.insert(name).second)
      throw InvalidInputError("invalid_parameter", "parameter '" + name + "' given more than once", {{"parameter", name}});
    if (parse_volume_param(name, value, out.volume, out.volume_given)) continue;
    if (name == "model") {
      if (value.empty()) invalid_parameter(name, "parameter model is empty", value);
      out.model = value;
    } else if (name == "lmax") {
      // Core's range first: below the features' minimum is a bad parameter (400); above the configured limit, which
      // finalize keeps within the SH fit's kShMaxFitLmax (and the min guards an unfinalised config), a size problem
      // (413), as the fit itself would say.
      const int lmax = parse_int(name, value, kMinFeatureLmax, std::numeric_limits<int>::max());
      const int allowed = std::min(config.max_lmax, kShMaxFitLmax);
      if (lmax > allowed)
        throw LimitExceededError("lmax=" + value + " exceeds the server's limit of " + std::to_string(allowed),
                                 {{"limit", std::string("lmax")}, {"value", std::int64_t{lmax}},
                                  {"allowed", std::int64_t{allowed}}});
      out.descriptor.lmax = lmax;
    } else if (name == "method") {
      // The one list of methods (core kMapMethodNames; proto/openapi.json's MapMethod schema is generated from it).
      const auto method = kMapMethodNames.find(lower(value));
      if (!method)
        invalid_parameter(name, "method must be " + kMapMethodNames.expected() + ", not '" + value + "'", value);
      out.descriptor.method = *method;
    } else if (name == "steps") {
      const int steps = parse_int(name, value, 1, 1000000);
      if (steps > config.max_steps)
        throw LimitExceededError("steps=" + value + " exceeds the server's limit of " + std::to_string(config.max_steps),
                                 {{"limit", std::string("steps")}, {"value", std::int64_t{steps}},
                                  {"allowed", std::int64_t{config.max_steps}}});
      out.descriptor.max_flow_steps = steps;
    } else if (name == "include") {
      out.include_coefficients = out.include_invariants = out.include_quality = out.include_reconstruction = false;
      out.include_mesh = out.include_sphere = out.include_distortion = false;
      std::size_t start = 0;
      while (start <= value.size()) {
        const auto comma = value.find(',', start);
        const std::string item = lower(trim(value.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
        if (item == "coefficients") out.include_coefficients = true;
        else if (item == "invariants") out.include_invariants = true;
        else if (item == "quality") out.include_quality = true;
        else if (item == "reconstruction") out.include_reconstruction = true;
        else if (item == "mesh") out.include_mesh = true;
        else if (item == "sphere") out.include_sphere = true;
        else if (item == "distortion") out.include_distortion = true;
        else if (!item.empty())
          invalid_parameter(name,
                        "include item '" + item +
                            "' is not one of coefficients, invariants, quality, reconstruction, mesh, sphere, distortion",
                        value);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else if (name == "output") {
      const std::string v = lower(value);
      if (v != "json" && v != "labels")
        invalid_parameter(name, "output must be json or labels, not '" + value + "'", value);
      if (v == "labels" && op != Operation::Classify)
        invalid_parameter(name, "output=labels writes a class map, which needs a model: use /v1/classify", value);
      out.output_labels = v == "labels";
      out.volume_given.push_back(name);  // a label volume's answer only: refused with a mesh part
    } else if (name == "reconstruction_level") {
      out.reconstruction_level = parse_int(name, value, 0, 7);
    } else if (name == "format") {
      const std::string f = lower(value);
      if (f != "obj" && f != "ply" && f != "off" && f != "stl")
        invalid_parameter(name, "format must be obj, ply, off or stl, not '" + value + "'", value);
      out.format = f;
    }
  }
  check_overrides(out.descriptor, "steps");  // a step cap with a one-shot method (linear, progressive) would be ignored
  return out;
}

std::vector<MeshPart> split_multipart(std::vector<FormPart> parts, ParamMap& params, const ServerConfig& config) {
  std::vector<MeshPart> meshes;
  for (auto& part : parts) {
    const bool is_mesh = !part.filename.empty() || starts_with(part.name, "mesh") || starts_with(part.name, "file");
    if (!is_mesh) {
      if (params.count(part.name))
        throw InvalidInputError("invalid_parameter", "parameter '" + part.name + "' given both in the query and the form",
                                {{"parameter", part.name}});
      params.emplace(part.name, part.content);
      continue;
    }
    if (static_cast<int>(meshes.size()) >= config.max_parts)
      throw WishError(ErrorCategory::TooLarge, "too_many_parts",
                      "more than " + std::to_string(config.max_parts) + " mesh parts in one request",
                      {{"limit", std::string("parts")}, {"allowed", std::int64_t{config.max_parts}}});
    meshes.push_back({part.name, part.filename, part.content_type,
                      std::make_shared<const std::string>(std::move(part.content))});
  }
  if (meshes.empty())
    throw InvalidInputError("no_mesh", "the multipart request has no mesh part (send a file part, e.g. curl -F mesh=@cell.ply)");
  return meshes;
}

MeshPart raw_body_part(std::string body, const std::string& content_type) {
  const std::string type = lower(trim(content_type.substr(0, content_type.find(';'))));
  if (type == "application/x-www-form-urlencoded" || type == "application/json")
    throw WishError(ErrorCategory::UnsupportedFormat, "unsupported_media_type",
                    "Content-Type " + type + " is not a mesh; send the file bytes with a mesh or octet-stream type "
                    "(curl --data-binary @m.ply -H 'Content-Type: application/octet-stream') or as multipart (curl -F mesh=@m.ply)",
                    {{"content_type", type}});
  if (body.empty()) throw InvalidInputError("no_mesh", "the request body is empty; send a mesh file");
  return {"", "", type, std::make_shared<const std::string>(std::move(body))};
}

std::string format_hint(const ComputeParams& params, const MeshPart& part) {
  if (!params.format.empty()) return params.format;
  const auto dot = part.filename.rfind('.');
  if (dot != std::string::npos) return lower(part.filename.substr(dot + 1));
  return part.content_type;
}

}  // namespace wish::server
