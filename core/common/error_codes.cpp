#include "core/common/error_codes.hpp"

#include <algorithm>
#include <array>

namespace wish {

namespace {

using C = ErrorCategory;
constexpr std::optional<ErrorCategory> kTransport = std::nullopt;

// Sorted by code (error_codes_test checks the order, so the binary search below is valid).
constexpr std::array kCodes{
    ErrorCodeInfo{"bad_config", C::InvalidInput, 0, "a configuration file or option of `wish serve` is malformed"},
    ErrorCodeInfo{"bad_request", C::InvalidInput, 0, "the HTTP request could not be read (framing, headers, body)"},
    ErrorCodeInfo{"box_too_large", C::TooLarge, 0, "a label-volume object's bounding box exceeds the voxel limit"},
    ErrorCodeInfo{"cancelled", C::Unavailable, 0, "the request was cancelled (client gone or server draining)"},
    ErrorCodeInfo{"decimation_failed", C::Internal, 0, "the decimater could not reduce an object surface"},
    ErrorCodeInfo{"degenerate_faces", C::Unmappable, 0, "faces repeat a vertex (zero-area faces alone are accepted; those that welding a twin vertex turns into repeats are dropped when the edge collapse is safe)"},
    ErrorCodeInfo{"degenerate_mesh", C::InvalidInput, 0, "the mesh has zero total area"},
    ErrorCodeInfo{"descriptor_mismatch", C::InvalidInput, 0, "a descriptor does not fit the model (length, Lmax)"},
    ErrorCodeInfo{"empty_mesh", C::InvalidInput, 0, "the file holds no vertices or no faces"},
    ErrorCodeInfo{"feature_mismatch", C::InvalidInput, 0, "features differ in length from what the model expects"},
    ErrorCodeInfo{"feature_spec", C::InvalidInput, 0, "an inconsistent feature specification (family, l range, scale)"},
    ErrorCodeInfo{"file_not_found", C::Io, 0, "a named file does not exist or cannot be opened for reading"},
    ErrorCodeInfo{"fit_failed", C::Internal, 0, "the SH normal equations could not be factorised"},
    ErrorCodeInfo{"generation_failed", C::InvalidInput, 0, "a synthetic demo shape gave no closed genus-0 surface"},
    ErrorCodeInfo{"genus_nonzero", C::Unmappable, 0, "the surface has handles (genus > 0): no sphere map exists"},
    ErrorCodeInfo{"inconsistent_orientation", C::Unmappable, 0, "neighbouring faces are oriented oppositely"},
    ErrorCodeInfo{"index_out_of_range", C::InvalidInput, 0, "a face refers to a vertex index the file does not have"},
    ErrorCodeInfo{"internal", C::Internal, 0, "a bug or an unexpected solver state (please report it)"},
    ErrorCodeInfo{"invalid_descriptor", C::InvalidInput, 0, "a descriptor value is malformed (not finite, wrong shape)"},
    ErrorCodeInfo{"invalid_descriptor_csv", C::InvalidInput, 0, "a descriptor CSV cannot be read"},
    ErrorCodeInfo{"invalid_label", C::InvalidInput, 0, "a class label is empty or malformed"},
    ErrorCodeInfo{"invalid_manifest", C::InvalidInput, 0, "a training manifest line is malformed (line number in details)"},
    ErrorCodeInfo{"invalid_parameter", C::InvalidInput, 0, "a request or command parameter is unknown, repeated or out of range"},
    ErrorCodeInfo{"invalid_recipe", C::InvalidInput, 0, "a descriptor recipe contradicts itself"},
    ErrorCodeInfo{"invalid_volume", C::InvalidInput, 0, "a label volume is malformed (size, dimensions, data)"},
    ErrorCodeInfo{"label_not_kept", C::InvalidInput, 0, "a label id a manifest names is not among the volume's kept objects"},
    ErrorCodeInfo{"limit_exceeded", C::TooLarge, 0, "a configured limit (vertices, faces, voxels, objects) was exceeded"},
    ErrorCodeInfo{"map_failed", C::Unmappable, 0, "no attempt of the map chain gave a verified bijective map (details.check)"},
    ErrorCodeInfo{"method_not_allowed", kTransport, 405, "the route exists but not for this HTTP method (see Allow)"},
    ErrorCodeInfo{"model_invalid", C::InvalidInput, 0, "a model file is malformed or inconsistent"},
    ErrorCodeInfo{"model_not_found", C::NotFound, 0, "no model of that name is loaded"},
    ErrorCodeInfo{"model_required", C::InvalidInput, 0, "the command needs a model and none was given"},
    ErrorCodeInfo{"model_version", C::InvalidInput, 0, "a model file's format version is not one this build reads"},
    ErrorCodeInfo{"multiple_components", C::Unmappable, 0, "the mesh has more than one connected component"},
    ErrorCodeInfo{"no_label", C::InvalidInput, 0, "a training file has no class label (folder or manifest)"},
    ErrorCodeInfo{"no_mesh", C::InvalidInput, 0, "a request carries no mesh"},
    ErrorCodeInfo{"no_model_loaded", C::Unavailable, 0, "classification was asked for but no model is loaded"},
    ErrorCodeInfo{"no_objects", C::Unmappable, 0, "a label volume has no object left to describe (all background, or all filtered out)"},
    ErrorCodeInfo{"non_finite_vertex", C::InvalidInput, 0, "a vertex coordinate is NaN or infinite"},
    ErrorCodeInfo{"non_manifold_edge", C::Unmappable, 0, "an edge is shared by more than two faces"},
    ErrorCodeInfo{"non_manifold_vertex", C::Unmappable, 0, "a vertex joins separate fans of faces"},
    ErrorCodeInfo{"not_closed", C::Unmappable, 0, "the mesh has boundary edges (it is open)"},
    ErrorCodeInfo{"not_found", kTransport, 404, "no such route"},
    ErrorCodeInfo{"not_manifold", C::Unmappable, 0, "a label-volume object's surface is not manifold"},
    ErrorCodeInfo{"not_ready", C::Unavailable, 0, "the service is starting or reloading"},
    ErrorCodeInfo{"off_recipe", C::Unmappable, 0, "the descriptor was computed otherwise than the model's recipe"},
    ErrorCodeInfo{"out_of_memory", kTransport, 503, "the server ran out of memory for this request; retry later"},
    ErrorCodeInfo{"parse_error", C::InvalidInput, 0, "the file's syntax is wrong (line and token in the message)"},
    ErrorCodeInfo{"payload_too_large", C::TooLarge, 0, "the request body exceeds the upload limit"},
    ErrorCodeInfo{"queue_full", C::Unavailable, 0, "the worker queue is full, or the work queued ahead would keep the request past its time limit; retry after Retry-After seconds"},
    ErrorCodeInfo{"report_not_found", C::NotFound, 0, "the model has no readable training report beside its file"},
    ErrorCodeInfo{"shutting_down", C::Unavailable, 0, "the server is draining for shutdown"},
    ErrorCodeInfo{"spectrum_failed", C::Internal, 0, "the Laplace-Beltrami eigenvalues (ShapeDNA) could not be computed (factorisation or convergence)"},
    ErrorCodeInfo{"timeout", C::Timeout, 0, "the per-request time limit passed"},
    ErrorCodeInfo{"too_many_parts", C::TooLarge, 0, "a multipart request has more parts than allowed"},
    ErrorCodeInfo{"too_small", C::Unmappable, 0, "fewer than 4 vertices or faces: not a closed surface"},
    ErrorCodeInfo{"training_data", C::InvalidInput, 0, "the training set is unusable (too few classes or samples)"},
    ErrorCodeInfo{"training_losses", C::InvalidInput, 0, "a class lost more meshes than allowed during training"},
    ErrorCodeInfo{"training_parameters", C::InvalidInput, 0, "inconsistent training options (grid, folds)"},
    ErrorCodeInfo{"unauthorized", kTransport, 401, "missing or wrong bearer token"},
    ErrorCodeInfo{"unavailable", kTransport, 503, "the service cannot answer now; retry later"},
    ErrorCodeInfo{"unsupported_datatype", C::InvalidInput, 0, "a volume's voxel type is not an integer or float label type"},
    ErrorCodeInfo{"unsupported_format", C::UnsupportedFormat, 0, "the file is not a mesh or volume format WISH reads"},
    ErrorCodeInfo{"unsupported_media_type", C::UnsupportedFormat, 0, "the request's Content-Type is not accepted"},
    ErrorCodeInfo{"uri_too_long", kTransport, 414, "the request URI is too long"},
    ErrorCodeInfo{"write_failed", C::Io, 0, "an output file could not be written"},
    ErrorCodeInfo{"zlib_error", C::Internal, 0, "zlib could not compress or initialise"},
};

}  // namespace

std::span<const ErrorCodeInfo> error_codes() { return kCodes; }

const ErrorCodeInfo* find_error_code(std::string_view code) {
  const auto it = std::lower_bound(kCodes.begin(), kCodes.end(), code,
                                   [](const ErrorCodeInfo& info, std::string_view c) { return info.code < c; });
  return it != kCodes.end() && it->code == code ? &*it : nullptr;
}

}  // namespace wish
