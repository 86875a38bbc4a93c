#pragma once
// Turning HTTP request pieces (query/form parameters, body, multipart parts) into typed compute parameters.
// Eigen-free and httplib-free: the HTTP file hands plain strings in. Every refusal is a WishError with a precise
// code, mapped to a status in error_mapping.cpp: invalid_parameter (400), limit_exceeded / too_many_parts (413),
// unsupported_media_type (415), no_mesh (400).

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/pipeline/describe_overrides.hpp"
#include "core/pipeline/volume_overrides.hpp"
#include "server/config.hpp"

namespace wish::server {

enum class Operation { Describe, Classify };

struct ComputeParams {
  std::string model;                  // classify: "" -> the default model
  // ?method= (a kMapMethodNames name), ?lmax=, ?steps= (the step cap of that method's flow), parsed once here;
  // absent: the defaults (describe) or the model's (classify).
  DescribeOverrides descriptor;
  bool include_coefficients = false;
  bool include_invariants = true;
  bool include_quality = true;
  bool include_reconstruction = false;
  bool include_mesh = false, include_sphere = false, include_distortion = false;  // the "geometry" block
  int reconstruction_level = 3;
  std::string format;                 // "obj" | "ply" | "off" | "stl" | "" (hint only; content detection wins)
  // A label volume's settings (?spacing=, ?unit=, ?objects=, ?threshold=, ?min_voxels=, ?fragment_gap=,
  // ?drop_truncated=, ?labels=, ?max_repair_share=, ?label_image=, ?level=): the typed value the CLI's flags fill too
  // (core/pipeline/volume_overrides.hpp). Only for volume parts: given with a mesh part they are refused, not ignored.
  VolumeOverrides volume;
  std::vector<std::string> volume_given;  // names of the volume parameters the request set
  // ?output=labels (classify, label volumes only): the answer carries the class map too, in the upload's format
  // (VolumeResult.class_map: core/pipeline/class_map.hpp, base64 in the JSON).
  bool output_labels = false;
  bool explicit_descriptor() const { return descriptor.any(); }
};

using ParamMap = std::multimap<std::string, std::string>;

// Unknown or repeated parameters are refused (a typo such as "lamx" must not be silently ignored).
ComputeParams parse_compute_params(Operation op, const ParamMap& params, const ServerConfig& config);

// One mesh to compute: the raw body, or one part of a multipart body.
struct MeshPart {
  std::string field;         // form field name ("" for a raw body)
  std::string filename;      // from the part's Content-Disposition, or ""
  std::string content_type;  // the part's or the request's Content-Type
  std::shared_ptr<const std::string> bytes;  // shared: a job may outlive the HTTP thread that waited for it
  bool volume = false;       // a label volume (NIfTI-1 / TIFF by content), set by the gateway: one result per object
};

struct FormPart {
  std::string name, filename, content_type, content;
};

// Multipart: parts with a filename, or named mesh* / file*, are meshes; other parts are parameters (merged into
// `params`; a parameter given both in the query and the form is refused). Throws no_mesh / too_many_parts.
std::vector<MeshPart> split_multipart(std::vector<FormPart> parts, ParamMap& params, const ServerConfig& config);

// Raw body: refuses form-encoded and JSON bodies (415) and empty bodies (400).
MeshPart raw_body_part(std::string body, const std::string& content_type);

// A format hint from ?format=, the part's file name extension, or the Content-Type; "" when none.
std::string format_hint(const ComputeParams& params, const MeshPart& part);

}  // namespace wish::server
