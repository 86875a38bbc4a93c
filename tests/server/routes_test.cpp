// The one route table (server/routes.hpp): behind the handlers' registration, 405 + Allow, and equal to the paths
// and methods of the contract the binary serves (proto/openapi.json, embedded).

#include "server/routes.hpp"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "server/openapi_document.hpp"

namespace wish::server {
namespace {

TEST(Routes, KnownPathsAndTheirMethods) {
  EXPECT_EQ(allowed_methods("/healthz", false), "GET, HEAD");
  EXPECT_EQ(allowed_methods("/v1/describe", false), "POST");
  EXPECT_EQ(allowed_methods("/v1/classify", true), "POST");
  EXPECT_EQ(allowed_methods("/v1/admin/reload", false), "POST");
  EXPECT_EQ(allowed_methods("/v1/models", false), "GET, HEAD");
  EXPECT_EQ(allowed_methods("/v1/models/default", false), "GET, HEAD");
  EXPECT_EQ(allowed_methods("/v1/models/default/report", false), "GET, HEAD");
}

TEST(Routes, UnknownPathsAreNotRoutes) {
  EXPECT_EQ(allowed_methods("/v1/models/a/b", false), "");  // one segment only
  EXPECT_EQ(allowed_methods("/v1/models/", false), "");
  EXPECT_EQ(allowed_methods("/v1/models//report", false), "");  // the name segment is not empty
  EXPECT_EQ(allowed_methods("/v1/models/a/report/x", false), "");
  EXPECT_EQ(allowed_methods("/v1/models/a/reports", false), "");
  EXPECT_EQ(allowed_methods("/healthz/", false), "");
  EXPECT_EQ(allowed_methods("/v1/describes", false), "");
  EXPECT_EQ(allowed_methods("/index.html", false), "");
  EXPECT_EQ(allowed_methods("/v1/nothing", true), "");      // the page never covers the API
  EXPECT_EQ(allowed_methods("/index.html", true), "GET, HEAD");  // the page's files
}

TEST(Routes, TableIsTheContractsPaths) {
  const auto doc = nlohmann::json::parse(openapi_document());
  std::map<std::string, std::set<std::string>> contract;
  for (const auto& [path, ops] : doc.at("paths").items()) {
    if (path == "/") continue;  // the web page, answered by the static files' route when it is on
    for (const auto& [method, op] : ops.items())
      if (method != "parameters" && method != "summary" && method != "description") contract[path].insert(method);
  }
  std::map<std::string, std::set<std::string>> table;
  for (const auto& r : routes()) {
    // The contract documents GET; HEAD is the HTTP library's answer to every GET route.
    table[r.path].insert(method_allowed(r.allow, "GET") ? "get" : "post");
    EXPECT_EQ(&route(r.id), &r) << r.path;
  }
  EXPECT_EQ(table, contract);
}

TEST(Routes, HttpPatternMatchesThePathsTheTableAnswers) {
  const std::regex model(http_pattern(route(RouteId::Model)));
  std::smatch m;
  const std::string path = "/v1/models/default";
  ASSERT_TRUE(std::regex_match(path, m, model));
  EXPECT_EQ(m[1], "default");
  EXPECT_FALSE(std::regex_match(std::string("/v1/models/a/b"), model));
  const std::regex openapi(http_pattern(route(RouteId::OpenApi)));
  EXPECT_TRUE(std::regex_match(std::string("/openapi.json"), openapi));
  EXPECT_FALSE(std::regex_match(std::string("/openapiXjson"), openapi));  // the dot is literal
}

TEST(Routes, MethodAllowed) {
  EXPECT_TRUE(method_allowed("GET, HEAD", "HEAD"));
  EXPECT_TRUE(method_allowed("POST", "POST"));
  EXPECT_FALSE(method_allowed("GET, HEAD", "POST"));
  EXPECT_FALSE(method_allowed("GET, HEAD", "GE"));
  EXPECT_FALSE(method_allowed("", "GET"));
}

}  // namespace
}  // namespace wish::server
