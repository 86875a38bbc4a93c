#pragma once
// The enums of proto/openapi.json that are core enums, made from their core name tables (core/common/enum_names.hpp):
// one schema per enum under components/schemas (MapMethod, FitWeighting, ...), which every use refers to with
// {"$ref": "#/components/schemas/MapMethod"}. The build writes them (wire/gen/contract_enums_main.cpp, run by
// server/CMakeLists.txt) into proto/openapi.json and into the document the service embeds, so that a name added to a
// core table is in the contract with no other edit; tests/wire/contract_enums_test.cpp checks the file agrees.

#include <string>
#include <vector>

namespace wish::wire {

struct ContractEnum {
  std::string schema;              // its name under components/schemas
  std::vector<std::string> names;  // the core table's names, in table order
  std::string description;         // says which table it is generated from
};

// Every core enum the contract shows, in the order they are written.
std::vector<ContractEnum> contract_enums();

// The schema's one-line JSON text: { "type": "string", "enum": [...], "description": "..." }.
std::string contract_enum_json(const ContractEnum& e);

// `openapi` (the text of proto/openapi.json) with each contract enum's schema written from its table: an existing
// components/schemas member's value is replaced, a missing one is inserted first in components/schemas. The rest
// of the text keeps its layout. Throws std::runtime_error when the text has no components/schemas object.
std::string with_contract_enums(const std::string& openapi);

}  // namespace wish::wire
