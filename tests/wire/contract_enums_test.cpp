// The core enums of the wire contract (wire/contract_enums.hpp) against their core name tables and proto/openapi.json:
//  * each enum's schema in the file lists exactly its table's names, in table order (the build writes them);
//  * no other place in the file lists a table's names inline: every use is a $ref to the one schema;
//  * with_contract_enums rewrites a stale schema and inserts a missing one, and leaves the rest of the text alone.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/spherical_map/map_types.hpp"
#include "wire/contract_enums.hpp"

namespace wish::wire {
namespace {

const std::filesystem::path kSource = WISH_TEST_SOURCE_DIR;

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

nlohmann::json contract() { return nlohmann::json::parse(read_text(kSource / "proto" / "openapi.json")); }

// Every "enum" array in the document with its JSON pointer.
void collect_enums(const nlohmann::json& node, const std::string& at,
                   std::vector<std::pair<std::string, std::vector<std::string>>>& out) {
  if (node.is_object()) {
    if (node.contains("enum") && node["enum"].is_array()) {
      std::vector<std::string> names;
      for (const auto& v : node["enum"])
        if (v.is_string()) names.push_back(v.get<std::string>());
      out.emplace_back(at, names);
    }
    for (const auto& [k, v] : node.items()) collect_enums(v, at + "/" + k, out);
  } else if (node.is_array()) {
    for (std::size_t i = 0; i < node.size(); ++i) collect_enums(node[i], at + "/" + std::to_string(i), out);
  }
}

TEST(ContractEnums, TheFileListsEachTablesNames) {
  const nlohmann::json doc = contract();
  const auto& schemas = doc.at("components").at("schemas");
  for (const ContractEnum& e : contract_enums()) {
    ASSERT_TRUE(schemas.contains(e.schema)) << e.schema << " missing from proto/openapi.json; build the service";
    EXPECT_EQ(schemas[e.schema].at("enum").get<std::vector<std::string>>(), e.names)
        << e.schema << ": proto/openapi.json is not the core table's; build the service (it rewrites the file)";
  }
  // The map methods are the core table's, whatever it holds.
  EXPECT_EQ(schemas["MapMethod"]["enum"].get<std::vector<std::string>>(), kMapMethodNames.names());
}

TEST(ContractEnums, NoTableIsListedInlineAnywhereElse) {
  const nlohmann::json doc = contract();
  std::vector<std::pair<std::string, std::vector<std::string>>> enums;
  collect_enums(doc, "", enums);
  for (const ContractEnum& e : contract_enums()) {
    const std::set<std::string> table(e.names.begin(), e.names.end());
    for (const auto& [at, names] : enums) {
      if (at == "/components/schemas/" + e.schema) continue;
      EXPECT_NE(std::set<std::string>(names.begin(), names.end()), table)
          << at << " lists " << e.schema << "'s names inline; refer to #/components/schemas/" << e.schema;
    }
  }
  // And the references resolve.
  const std::string text = doc.dump();
  for (const ContractEnum& e : contract_enums())
    EXPECT_NE(text.find("\"$ref\":\"#/components/schemas/" + e.schema + "\""), std::string::npos)
        << e.schema << " is generated but never referred to";
}

TEST(ContractEnums, AStaleSchemaIsRewrittenAndAMissingOneInserted) {
  const std::string stale =
      "{\n  \"components\": {\n    \"schemas\": {\n      \"Other\": { \"type\": \"integer\" },\n"
      "      \"MapMethod\": { \"type\": \"string\", \"enum\": [\"willmore\", \"spectral\"] },\n"
      "      \"Last\": { \"description\": \"a } and a \\\" in a string\" }\n    }\n  }\n}\n";
  const std::string fixed = with_contract_enums(stale);
  const nlohmann::json doc = nlohmann::json::parse(fixed);
  const auto& schemas = doc["components"]["schemas"];
  for (const ContractEnum& e : contract_enums())
    EXPECT_EQ(schemas.at(e.schema).at("enum").get<std::vector<std::string>>(), e.names) << e.schema;
  EXPECT_EQ(schemas["Other"], nlohmann::json({{"type", "integer"}}));
  EXPECT_EQ(schemas["Last"]["description"], "a } and a \" in a string");
  EXPECT_EQ(with_contract_enums(fixed), fixed);  // idempotent: a second build changes nothing
}

}  // namespace
}  // namespace wish::wire
