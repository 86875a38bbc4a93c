// The one list of error codes (core/common/error_codes.hpp) against the code that throws and the wire contract:
//  * every code literal thrown in core/, server/ or cli/ is listed, with the category it is thrown with;
//  * the enum of Error.code in proto/openapi.json is exactly the list;
//  * the list is sorted and has no duplicates (find_error_code relies on it).
// The source scan reads the repository (WISH_TEST_SOURCE_DIR); the patterns are the throw forms the code uses.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "core/common/error_codes.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kSource = WISH_TEST_SOURCE_DIR;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::optional<wish::ErrorCategory> category_named(const std::string& name) {
  using C = wish::ErrorCategory;
  static const std::map<std::string, C> names{
      {"InvalidInput", C::InvalidInput}, {"UnsupportedFormat", C::UnsupportedFormat}, {"TooLarge", C::TooLarge},
      {"Unmappable", C::Unmappable},     {"NotFound", C::NotFound},                   {"Timeout", C::Timeout},
      {"Unavailable", C::Unavailable},   {"Internal", C::Internal},                   {"Io", C::Io}};
  const auto it = names.find(name);
  if (it == names.end()) return std::nullopt;
  return it->second;
}

struct Use {
  std::string code;
  std::optional<wish::ErrorCategory> category;  // known from the throw form, else only "must be listed"
  std::string where;
};

// Every code literal in the C++ sources of the three front ends of the code.
std::vector<Use> code_uses() {
  struct Pattern {
    std::regex rx;
    int code_group;
    std::function<std::optional<wish::ErrorCategory>(const std::smatch&)> category;
  };
  using C = wish::ErrorCategory;
  auto fixed = [](std::optional<C> c) { return [c](const std::smatch&) { return c; }; };
  const std::vector<Pattern> patterns{
      {std::regex(R"(\bInvalidInputError\(\s*"([a-z0-9_]+)\")"), 1, fixed(C::InvalidInput)},
      {std::regex(R"(\bIoError\(\s*"([a-z0-9_]+)\")"), 1, fixed(C::Io)},
      {std::regex(R"(\bWishError\(\s*ErrorCategory::(\w+),\s*"([a-z0-9_]+)\")"), 2,
       [](const std::smatch& m) { return category_named(m[1].str()); }},
      // The HTTP front's own answers: ApiError{status, "code", ...}.
      {std::regex(R"(\{\s*[1-5][0-9][0-9],\s*"([a-z0-9_]+)\")"), 1, fixed(std::nullopt)},
      // Validation findings (core/validation/mesh_repair.cpp add("code", ...)), refused as Unmappable.
      {std::regex(R"(\badd\(\s*"([a-z0-9_]+)\")"), 1, fixed(C::Unmappable)},
      // Per-object refusals of label volumes and per-file skips in training reports.
      {std::regex(R"(refusal_code\s*=\s*"([a-z0-9_]+)\")"), 1, fixed(std::nullopt)},
      {std::regex(R"(\{\s*"code",\s*"([a-z0-9_]+)\"\s*\})"), 1, fixed(std::nullopt)},
      // Default code arguments: `const std::string& code = "invalid_recipe"`.
      {std::regex(R"(\bcode\s*=\s*"([a-z0-9_]+)\")"), 1, fixed(std::nullopt)},
  };
  std::vector<Use> uses;
  for (const char* dir : {"core", "server", "cli"}) {
    for (const auto& entry : fs::recursive_directory_iterator(kSource / dir)) {
      const auto ext = entry.path().extension();
      if (ext != ".cpp" && ext != ".hpp") continue;
      if (entry.path().filename() == "error_codes.cpp") continue;  // the list itself
      const std::string text = read_text(entry.path());
      for (const auto& p : patterns) {
        for (std::sregex_iterator it(text.begin(), text.end(), p.rx), end; it != end; ++it) {
          const std::smatch& m = *it;
          const auto line = 1 + std::count(text.begin(), text.begin() + m.position(0), '\n');
          uses.push_back({m[p.code_group].str(), p.category(m),
                          fs::relative(entry.path(), kSource).string() + ":" + std::to_string(line)});
        }
      }
      // The two subclasses whose code is fixed by the class.
      if (text.find("LimitExceededError(") != std::string::npos)
        uses.push_back({"limit_exceeded", C::TooLarge, entry.path().filename().string()});
      if (std::regex_search(text, std::regex(R"(\bTimeoutError\()")))
        uses.push_back({"timeout", C::Timeout, entry.path().filename().string()});
    }
  }
  return uses;
}

}  // namespace

TEST(ErrorCodes, ListIsSortedUniqueAndComplete) {
  const auto codes = wish::error_codes();
  ASSERT_GT(codes.size(), 30u);
  for (std::size_t i = 1; i < codes.size(); ++i)
    EXPECT_LT(codes[i - 1].code, codes[i].code) << "error_codes.cpp must stay sorted: " << codes[i].code;
  for (const auto& info : codes) {
    EXPECT_FALSE(info.meaning.empty()) << info.code;
    EXPECT_TRUE(std::regex_match(std::string(info.code), std::regex("[a-z][a-z0-9_]*"))) << info.code;
    // A transport-only code says which status the HTTP front gives it; a core code gets its status from the category.
    EXPECT_EQ(info.category.has_value(), info.transport_status == 0) << info.code;
    EXPECT_EQ(wish::find_error_code(info.code), &info);
  }
  EXPECT_EQ(wish::find_error_code("no_such_code_anywhere"), nullptr);
}

TEST(ErrorCodes, EveryThrownCodeIsListedWithItsCategory) {
  if (!fs::exists(kSource / "core")) GTEST_SKIP() << "source tree not found at " << kSource;
  const auto uses = code_uses();
  ASSERT_GT(uses.size(), 100u) << "the source scan found too few throw sites: have the throw forms changed?";
  for (const auto& use : uses) {
    const auto* info = wish::find_error_code(use.code);
    ASSERT_NE(info, nullptr) << "code \"" << use.code << "\" at " << use.where
                             << " is not listed in core/common/error_codes.cpp";
    if (use.category && info->category) {
      EXPECT_EQ(*use.category, *info->category)
          << "\"" << use.code << "\" at " << use.where << " is thrown as " << wish::to_string(*use.category)
          << " but listed as " << wish::to_string(*info->category);
    }
  }
}

TEST(ErrorCodes, OpenApiEnumEqualsTheList) {
  const fs::path openapi = kSource / "proto" / "openapi.json";
  if (!fs::exists(openapi)) GTEST_SKIP() << openapi << " not found";
  const auto doc = nlohmann::json::parse(read_text(openapi));
  const auto& code = doc.at("components").at("schemas").at("Error").at("properties").at("error").at("properties").at("code");
  ASSERT_TRUE(code.contains("enum")) << "Error.code in openapi.json has no enum";
  std::set<std::string> in_contract = code.at("enum").get<std::set<std::string>>();
  std::set<std::string> listed;
  for (const auto& info : wish::error_codes()) listed.insert(std::string(info.code));
  for (const auto& c : listed) EXPECT_TRUE(in_contract.count(c)) << c << " is listed but missing in openapi.json (run scripts/gen-error-codes.py)";
  for (const auto& c : in_contract) EXPECT_TRUE(listed.count(c)) << c << " is in openapi.json but not listed in error_codes.cpp";
}
