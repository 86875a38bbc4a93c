// The route table behind 405 + Allow (server/routes.hpp).

#include "server/routes.hpp"

#include <gtest/gtest.h>

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

TEST(Routes, MethodAllowed) {
  EXPECT_TRUE(method_allowed("GET, HEAD", "HEAD"));
  EXPECT_TRUE(method_allowed("POST", "POST"));
  EXPECT_FALSE(method_allowed("GET, HEAD", "POST"));
  EXPECT_FALSE(method_allowed("GET, HEAD", "GE"));
  EXPECT_FALSE(method_allowed("", "GET"));
}

}  // namespace
}  // namespace wish::server
