// Error mapping (server/error_mapping.hpp): one status per category, the one error body, and what becomes of
// exceptions that are not WishErrors.

#include "server/error_mapping.hpp"

#include <map>
#include <new>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/common/error_codes.hpp"
#include "server/openapi_document.hpp"

namespace wish::server {
namespace {

TEST(ErrorMapping, OneStatusPerCategory) {
  // Every category has exactly one entry in the table (kCategoryStatus); a few statuses clients rely on.
  std::set<ErrorCategory> seen;
  for (const auto& entry : category_statuses()) {
    EXPECT_TRUE(seen.insert(entry.category).second) << to_string(entry.category) << " listed twice";
    EXPECT_EQ(http_status(entry.category), entry.status);
  }
  EXPECT_EQ(seen.size(), 9u);
  EXPECT_EQ(http_status(ErrorCategory::TooLarge), 413);
  EXPECT_EQ(http_status(ErrorCategory::Unmappable), 422);
  EXPECT_EQ(http_status(ErrorCategory::Unavailable), 503);
}

// The contract the binary serves (proto/openapi.json, embedded) says what the table says: Error.code's statuses
// (written by scripts/gen-error-codes.py from the table) and a response for every status a compute route can give.
TEST(ErrorMapping, ContractStatusesFollowTheTable) {
  const auto doc = nlohmann::json::parse(openapi_document());
  const std::string summary = doc.at("components").at("schemas").at("Error").at("properties").at("error")
                                  .at("properties").at("code").at("description").get<std::string>();
  const auto by_status = summary.find("By HTTP status: ");
  ASSERT_NE(by_status, std::string::npos) << summary;
  std::map<std::string, int> contract_status;  // code -> status as the contract groups it
  const std::regex group(R"((\d{3}): ([a-z0-9_, ]+)[;.])");
  const std::string groups = summary.substr(by_status);
  for (std::sregex_iterator it(groups.begin(), groups.end(), group), end; it != end; ++it) {
    const int status = std::stoi((*it)[1].str());
    std::stringstream codes((*it)[2].str());
    for (std::string code; std::getline(codes, code, ',');) {
      code.erase(0, code.find_first_not_of(' '));
      contract_status[code] = status;
    }
  }
  for (const auto& info : error_codes()) {
    const int status = info.category ? http_status(*info.category) : info.transport_status;
    EXPECT_EQ(contract_status[std::string(info.code)], status)
        << info.code << ": the contract's status differs from the table (run scripts/gen-error-codes.py)";
  }
  for (const char* path : {"/v1/describe", "/v1/classify"}) {
    const auto& responses = doc.at("paths").at(path).at("post").at("responses");
    for (const auto category : {ErrorCategory::InvalidInput, ErrorCategory::UnsupportedFormat, ErrorCategory::TooLarge,
                                ErrorCategory::Unmappable, ErrorCategory::Timeout, ErrorCategory::Unavailable})
      EXPECT_TRUE(responses.contains(std::to_string(http_status(category)))) << path << " " << to_string(category);
  }
}

TEST(ErrorMapping, WishErrorKeepsCodeMessageAndTypedDetails) {
  const ApiError e = to_api_error(WishError(ErrorCategory::TooLarge, "limit_exceeded", "too many vertices",
                                            {{"limit", std::string("vertices")}, {"value", std::int64_t{12}},
                                             {"ratio", 0.5}}));
  EXPECT_EQ(e.status, 413);
  EXPECT_EQ(e.code, "limit_exceeded");
  EXPECT_EQ(e.message, "too many vertices");
  EXPECT_EQ(e.details["limit"], "vertices");
  EXPECT_TRUE(e.details["value"].is_number_integer());
  EXPECT_DOUBLE_EQ(e.details["ratio"].get<double>(), 0.5);
  EXPECT_EQ(e.retry_after_seconds, 0);  // only 503s ask for a retry
}

TEST(ErrorMapping, EmptyCodeFallsBackToTheCategory) {
  const ApiError e = to_api_error(WishError(ErrorCategory::Unmappable, "", "no map"));
  EXPECT_EQ(e.code, to_string(ErrorCategory::Unmappable));
}

TEST(ErrorMapping, UnavailableCarriesTheConfiguredRetryAfter) {
  set_retry_after_seconds(7);
  EXPECT_EQ(to_api_error(WishError(ErrorCategory::Unavailable, "queue_full", "full")).retry_after_seconds, 7);
  set_retry_after_seconds(0);  // refused: at least 1 s
  EXPECT_EQ(to_api_error(WishError(ErrorCategory::Unavailable, "queue_full", "full")).retry_after_seconds, 1);
}

TEST(ErrorMapping, ForeignExceptions) {
  const ApiError oom = to_api_error(std::make_exception_ptr(std::bad_alloc()));
  EXPECT_EQ(oom.status, 503);
  EXPECT_EQ(oom.code, "out_of_memory");
  EXPECT_GT(oom.retry_after_seconds, 0);
  const ApiError bug = to_api_error(std::make_exception_ptr(std::logic_error("index 7")));
  EXPECT_EQ(bug.status, 500);
  EXPECT_EQ(bug.code, "internal");
  EXPECT_NE(bug.message.find("index 7"), std::string::npos);
  EXPECT_EQ(to_api_error(std::make_exception_ptr(42)).status, 500);
  const ApiError typed = to_api_error(std::make_exception_ptr(TimeoutError("late", {})));
  EXPECT_EQ(typed.status, 504);
}

TEST(ErrorMapping, HttpLayerErrors) {
  EXPECT_EQ(unauthorized_error().status, 401);
  const ApiError nf = route_not_found_error("GET", "/v2/x");
  EXPECT_EQ(nf.status, 404);
  EXPECT_EQ(nf.details["path"], "/v2/x");
  EXPECT_EQ(status_error(413).code, "payload_too_large");
  EXPECT_EQ(status_error(414).code, "uri_too_long");
  EXPECT_EQ(status_error(400).code, "bad_request");
  EXPECT_EQ(status_error(431).status, 431);
  EXPECT_EQ(status_error(502).code, "internal");
}

TEST(ErrorMapping, TheOneErrorBody) {
  const ApiError e = to_api_error(InvalidInputError("invalid_parameter", "lmax is not an integer", {{"parameter", std::string("lmax")}}));
  const nlohmann::json body = error_body(e, "abc");
  EXPECT_EQ(body["request_id"], "abc");
  EXPECT_EQ(body["error"]["code"], "invalid_parameter");
  EXPECT_EQ(body["error"]["message"], "lmax is not an integer");
  EXPECT_EQ(body["error"]["details"]["parameter"], "lmax");
  EXPECT_EQ(body.size(), 2u);
  EXPECT_EQ(body["error"].size(), 3u);
}

}  // namespace
}  // namespace wish::server
