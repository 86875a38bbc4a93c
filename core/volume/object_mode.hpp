#pragma once
// How the objects of a label image are found, and its wire names: one table (core/common/enum_names.hpp) that the
// CLI's --objects (cli/enum_option.hpp), the service's ?objects= (server/request_parsing.cpp) and the OpenAPI
// ObjectMode schema (wire/contract_enums.cpp) are all made from. Eigen-free, so the service's request types can hold
// one.
//   auto        decided from the values (input_kind.hpp): labels, or components of a (soft) mask / probability map
//   labels      each distinct non-zero value is one object
//   components  the 6-connected components of the foreground (value >= threshold, or non-zero)

#include "core/common/enum_names.hpp"

namespace wish::volume {

enum class ObjectMode { Auto, Labels, Components };
inline constexpr EnumNames<ObjectMode, 3> kObjectModeNames{{{
    {ObjectMode::Auto, "auto"},
    {ObjectMode::Labels, "labels"},
    {ObjectMode::Components, "components"}}}};
inline const char* to_string(ObjectMode mode) { return kObjectModeNames.name(mode); }

}  // namespace wish::volume
