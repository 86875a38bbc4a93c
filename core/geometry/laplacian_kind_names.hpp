#pragma once
// The name table of LaplacianKind (intrinsic_laplacian.hpp): to_string / laplacian_kind_from_name and the OpenAPI
// LaplacianKind schema (wire/contract_enums.cpp).

#include "core/common/enum_names.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"

namespace wish::geometry {

inline constexpr EnumNames<LaplacianKind, 3> kLaplacianKindNames{{{
    {LaplacianKind::Extrinsic, "extrinsic"},
    {LaplacianKind::Mollified, "mollified"},
    {LaplacianKind::IntrinsicDelaunay, "intrinsic_delaunay"}}}};

}  // namespace wish::geometry
