#pragma once
// The one list of map method names (MapMethod, spherical_map.hpp): to_string / map_method_from_name, the CLI's
// --method choices (cli/enum_option.hpp), the service's `method` parameter (server/request_parsing.cpp) and the
// OpenAPI MapMethod schema (wire/contract_enums.cpp) are all made from it, so adding a method here is the only
// change those need.

#include "core/common/enum_names.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish {

inline constexpr EnumNames<MapMethod, 3> kMapMethodNames{{{
    {MapMethod::Willmore, "willmore"},
    {MapMethod::Cmcf, "cmcf"},
    {MapMethod::Linear, "linear"}}}};

}  // namespace wish
