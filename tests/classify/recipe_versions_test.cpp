// The recipe's version table (core/classify/descriptor_recipe_codec.hpp, issue 27): every member of the recipe's
// structs has a line in it, every key a model file writes is one of its lines (and the other way round), and the
// version written to a file is the highest version among the fields away from their legacy values.
// A member added to SphericalMapOptions, CmcfOptions, ... without a line in the table fails
// EveryMemberOfTheRecipeStructsHasAnEntry: its member count no longer matches the table's keys.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/classify/classifier_model.hpp"
#include "core/classify/descriptor_recipe_codec.hpp"
#include "core/classify/model_json_codec.hpp"
#include "core/classify/sha256.hpp"
#include "core/common/errors.hpp"
#include "tests/classify/classify_test_data.hpp"

namespace wish {
namespace {

// ---- the number of members of an aggregate: the most initialisers T{...} accepts ----
struct AnyMember {
  template <class T> constexpr operator T() const noexcept;  // unevaluated only
};
template <class T, class... A> constexpr std::size_t member_count() {
  if constexpr (requires { T{A{}..., AnyMember{}}; }) return member_count<T, A..., AnyMember>();
  else return sizeof...(A);
}

// ---- the table, as visit_recipe() lists it ----
struct Entry {
  int since = 1;
  enum Kind { Field, Group, Retired, Derived } kind = Field;
};
struct TableLister {
  std::string where;
  std::map<std::string, Entry>* table;
  void put(const char* key, Entry e) { (*table)[where.empty() ? key : where + "." + key] = e; }
  template <class T> void field(const char* key, const T&) { put(key, {1, Entry::Field}); }
  template <class F> void group(const char* key, F&& fill) { nested(1, key, fill); }
  template <class T> void added(int since, const char* key, const T&, const T&) { put(key, {since, Entry::Field}); }
  template <class F, class T> void added_group(int since, const char* key, F&& fill, const T&, const T&) {
    nested(since, key, fill);
  }
  template <class T> void retired(const char* key, int last, const T&) { put(key, {last, Entry::Retired}); }
  void derived(const char* key) { put(key, {1, Entry::Derived}); }

 private:
  template <class F> void nested(int since, const char* key, F&& fill) {
    put(key, {since, Entry::Group});
    TableLister sub{where.empty() ? key : where + "." + key, table};
    fill(sub);
  }
};

std::map<std::string, Entry> version_table() {
  std::map<std::string, Entry> table;
  TableLister lister{"", &table};
  DescriptorRecipe r;
  visit_recipe(lister, r);
  return table;
}

// Keys of one group of the table that a recipe struct's members stand for (not retired, not derived).
std::size_t member_keys(const std::map<std::string, Entry>& table, const std::string& group) {
  std::size_t n = 0;
  for (const auto& [path, e] : table) {
    if (e.kind == Entry::Retired || e.kind == Entry::Derived) continue;
    const auto dot = path.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : path.substr(0, dot);
    if (parent == group) ++n;
  }
  return n;
}

void collect_paths(const nlohmann::json& j, const std::string& where, std::set<std::string>& out) {
  for (const auto& [key, value] : j.items()) {
    const std::string path = where.empty() ? key : where + "." + key;
    out.insert(path);
    if (value.is_object()) collect_paths(value, path, out);
  }
}

TEST(RecipeVersions, EveryMemberOfTheRecipeStructsHasAnEntry) {
  const auto table = version_table();
  EXPECT_EQ(member_keys(table, ""), member_count<DescriptorRecipe>());
  // SphericalMapOptions::prefer_method is derived from the off-recipe policy at run time and needle_aware is an A/B
  // switch for measurements: neither is part of the recipe.
  EXPECT_EQ(member_keys(table, "map"), member_count<SphericalMapOptions>() - 2);
  // WillmoreOptions::needle_operator is set per attempt by the chain's needle retry (map_attempt.cpp), not a recipe
  // choice.
  EXPECT_EQ(member_keys(table, "map.willmore"), member_count<WillmoreOptions>() - 1);
  EXPECT_EQ(member_keys(table, "map.cmcf"), member_count<CmcfOptions>());
  EXPECT_EQ(member_keys(table, "map.linear"), member_count<LinearMapOptions>());
  EXPECT_EQ(member_keys(table, "map.verification"), member_count<MapVerificationThresholds>());
  EXPECT_EQ(member_keys(table, "map.laplacian"), member_count<geometry::IntrinsicOptions>());
  EXPECT_EQ(member_keys(table, "map.area_correction"), member_count<AreaCorrectionOptions>());
  EXPECT_EQ(member_keys(table, "sh"), member_count<ShFitOptions>());
  EXPECT_EQ(member_keys(table, "features"), member_count<FeatureSpec>());
  for (const auto& [path, e] : table) {
    EXPECT_GE(e.since, 1) << path;
    EXPECT_LE(e.since, DescriptorRecipe::kVersion) << path;
  }
}

TEST(RecipeVersions, EveryKeyWrittenIsInTheTableAndEveryEntryIsWritten) {
  const auto table = version_table();
  DescriptorRecipe recipe;  // today's defaults: every field away from its legacy value somewhere ...
  recipe.map.canonical.method = CanonicalMap::Isometric;  // ... but the version-5 fields (off by default)
  recipe.sh.sampling = FitSampling::Surface;
  const nlohmann::json j = recipe_to_json(recipe);
  ASSERT_EQ(j.at("recipe_version"), DescriptorRecipe::kVersion);
  std::set<std::string> written;
  collect_paths(j, "", written);
  written.erase("recipe_version");
  std::set<std::string> listed;
  for (const auto& [path, e] : table)
    if (e.kind != Entry::Retired) listed.insert(path);
  // Group members below a group key are listed as well, so both sets hold full paths.
  std::vector<std::string> not_listed, not_written;
  for (const auto& p : written)
    if (!listed.count(p)) not_listed.push_back(p);
  for (const auto& p : listed)
    if (!written.count(p)) not_written.push_back(p);
  EXPECT_TRUE(not_listed.empty()) << "written without a version entry: " << ::testing::PrintToString(not_listed);
  EXPECT_TRUE(not_written.empty()) << "in the table but not written: " << ::testing::PrintToString(not_written);
}

// Sets every later field to its legacy value (the recipe of a version-1 build), or moves the k-th one away from it:
// a number by +1, a switch flipped, an added enumeration to another value; in a group every number and switch (an enumeration stays: any of its values may
// be the legacy one).
struct Legacy {
  int k = -1;  // which added field to move away from its legacy value (-1: none)
  int index = 0;
  int since_of_k = 0;
  bool moving = false;  // inside the group being moved
  template <class T> void field(const char*, T& v) {
    if constexpr (!std::is_enum_v<T>)
      if (moving) v = moved(v);
  }
  template <class F> void group(const char*, F&& fill) { fill(*this); }
  template <class T> void added(int since, const char*, T& value, const T& legacy) {
    value = legacy;
    if (index++ == k) {
      since_of_k = since;
      value = moved(value);
    }
  }
  template <class F, class T> void added_group(int since, const char*, F&& fill, T& target, const T& legacy) {
    target = legacy;
    if (index++ == k) {
      since_of_k = since;
      moving = true;
      fill(*this);
      moving = false;
    }
  }
  template <class T> void retired(const char*, int, const T&) {}
  void derived(const char*) {}

  template <class T> static T moved(T v) {
    if constexpr (std::is_same_v<T, bool>) return !v;
    else if constexpr (std::is_enum_v<T>) return static_cast<T>(static_cast<int>(v) == 0 ? 1 : 0);  // another value
    else return v + 1;
  }
};

// A sealed model file whose recipe is `recipe` (features as the trained model's, so the rest stays consistent).
std::string model_text_with(const ClassifierModel& model, const DescriptorRecipe& recipe) {
  auto doc = nlohmann::json::parse(model.to_json_text());
  doc["payload"]["recipe"] = recipe_to_json(recipe);
  doc["payload_sha256"] = Sha256::hex(doc["payload"].dump());
  return doc.dump();
}

const ClassifierModel& small_model() {
  static const ClassifierModel model = [] {
    auto opts = testing::quick_train_options();
    opts.nested_repeats = 0;
    return train_classifier(testing::synthetic_samples(2, 8, 3), opts).model;
  }();
  return model;
}

TEST(RecipeVersions, AllLegacyRecipeIsVersion1AndWritesOnlyVersion1Keys) {
  DescriptorRecipe recipe = small_model().recipe();
  Legacy legacy;
  visit_recipe(legacy, recipe);
  ASSERT_GT(legacy.index, 0);
  EXPECT_EQ(recipe_version_of(recipe), 1);
  const nlohmann::json j = recipe_to_json(recipe);
  EXPECT_EQ(j.at("recipe_version"), 1);
  const auto table = version_table();
  std::set<std::string> written;
  collect_paths(j, "", written);
  for (const auto& p : written) {
    if (p == "recipe_version") continue;
    EXPECT_EQ(table.at(p).since, 1) << p;
  }
  const auto loaded = ClassifierModel::from_json_text(model_text_with(small_model(), recipe));
  EXPECT_TRUE(loaded.recipe() == recipe);
}

TEST(RecipeVersions, FileVersionIsTheVersionOfTheFieldAwayFromItsLegacyValue) {
  DescriptorRecipe base = small_model().recipe();
  Legacy count;
  visit_recipe(count, base);
  std::set<int> versions_seen;
  for (int k = 0; k < count.index; ++k) {
    DescriptorRecipe recipe = small_model().recipe();
    Legacy move{k};
    visit_recipe(move, recipe);
    versions_seen.insert(move.since_of_k);
    EXPECT_EQ(recipe_version_of(recipe), move.since_of_k) << "added field #" << k;
    const nlohmann::json j = recipe_to_json(recipe);
    EXPECT_EQ(j.at("recipe_version"), move.since_of_k);
    const auto loaded = ClassifierModel::from_json_text(model_text_with(small_model(), recipe));
    EXPECT_TRUE(loaded.recipe() == recipe) << "added field #" << k << " did not survive its file";
  }
  EXPECT_EQ(versions_seen, (std::set<int>{2, 3, 4, 5}));
}

}  // namespace
}  // namespace wish
