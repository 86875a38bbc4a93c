#pragma once
// The one JSON layout of an SH descriptor (used by `wish describe`, `wish reconstruct` and the server):
// {
//   "lmax": L,
//   "options": {"lmax", "regularization", "weighting": "area"|"uniform", "solver": "direct"|"banded", "band_size",
//               "gram": "quadrature"|"product"},
//   "index": "j = l^2 + l + m",
//   "coefficients": {"x": [[re, im], ...], "y": [...], "z": [...]},   // (L+1)^2 pairs each, in index order j
//   "invariants": [xi_0, ..., xi_L],                                  // sum over x, y, z
//   "fit_error": {"mean", "rms", "max", "mean_relative", "rms_relative", "max_relative"}
// }

#include <nlohmann/json.hpp>

#include "core/sh/sh_descriptor.hpp"

namespace wish::cli {

nlohmann::json descriptor_to_json(const ShDescriptor& descriptor);
nlohmann::json fit_options_to_json(const ShFitOptions& options);

// Accepts the layout above; also a `wish describe --json` entry ({"descriptor": {...}, ...}).
// Throws InvalidInputError ("invalid_descriptor") with the offending field in the message.
ShDescriptor descriptor_from_json(const nlohmann::json& json);

}  // namespace wish::cli
