#pragma once
// The range of Lmax the SH fit accepts (fit_spherical_harmonics refuses anything else): the one statement of it.
// Every edge reads these constants and never restates them (issue 37 item 5): `wish describe --lmax`, `wish train
// --lmax` (with the feature pipeline's minimum, core/classify/feature_pipeline.hpp), the service's max_lmax and a
// request's lmax, the model file's and the recipe's checks, and proto/openapi.json (tests/wire/contract_bounds_test
// compares the file with them).
//
// Why 64: the fit solves k x k normal equations, k = (Lmax+1)^2 coefficients per coordinate, so its memory grows as
// Lmax^4 (Lmax 64: k = 4225, 143 MB of doubles per Gram matrix); the descriptors that classify use Lmax 10..15.
// Lmax 0 is a fit (xi(0) alone: the centroid's energy), legal but of no use as a shape feature.

namespace wish {

inline constexpr int kShMinFitLmax = 0;
inline constexpr int kShMaxFitLmax = 64;

}  // namespace wish
