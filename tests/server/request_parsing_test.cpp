// Request parsing (server/request_parsing.hpp): typed parameters from plain strings, multipart parts split into
// meshes and parameters, raw bodies; each refusal with its code and the offending parameter.

#include "server/request_parsing.hpp"

#include <gtest/gtest.h>

#include "core/classify/feature_pipeline.hpp"
#include "core/common/errors.hpp"
#include "core/sh/sh_lmax_range.hpp"
#include "core/spherical_map/map_types.hpp"

namespace wish::server {
namespace {

ServerConfig config() {
  ServerConfig c;
  c.max_lmax = 20;
  c.max_steps = 50;
  c.max_parts = 2;
  return c;
}

// The WishError `f` throws (fails the test when it throws none).
template <class F>
WishError thrown(F f) {
  try {
    f();
  } catch (const WishError& e) {
    return e;
  }
  ADD_FAILURE() << "no WishError thrown";
  return WishError(ErrorCategory::Internal, "none", "none");
}

std::string detail(const WishError& e, const std::string& key) {
  for (const auto& [k, v] : e.details())
    if (k == key) return std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : "(number)";
  return "(absent)";
}

TEST(ParseComputeParams, DefaultsWhenNothingIsGiven) {
  const ComputeParams p = parse_compute_params(Operation::Describe, {}, config());
  EXPECT_FALSE(p.explicit_descriptor());
  EXPECT_TRUE(p.include_invariants);
  EXPECT_TRUE(p.include_quality);
  EXPECT_FALSE(p.include_coefficients);
  EXPECT_EQ(p.reconstruction_level, 3);
}

TEST(ParseComputeParams, TypedValuesAreTrimmedAndLowered) {
  const ComputeParams p = parse_compute_params(
      Operation::Classify,
      {{"lmax", " 12 "}, {"method", "CMCF"}, {"steps", "30"}, {"model", "m1"}, {"include", "Coefficients, mesh"},
       {"format", "PLY"}},
      config());
  EXPECT_EQ(p.descriptor.lmax, 12);
  EXPECT_EQ(p.descriptor.method, MapMethod::Cmcf);  // typed once, here
  EXPECT_EQ(p.descriptor.max_flow_steps, 30);
  EXPECT_EQ(p.model, "m1");
  EXPECT_TRUE(p.include_coefficients);
  EXPECT_TRUE(p.include_mesh);
  EXPECT_FALSE(p.include_invariants);  // include= replaces the default set
  EXPECT_EQ(p.format, "ply");
  EXPECT_TRUE(p.explicit_descriptor());
}

TEST(ParseComputeParams, RefusalsNameTheParameter) {
  const ServerConfig c = config();
  auto e = thrown([&] { parse_compute_params(Operation::Describe, {{"lamx", "4"}}, c); });
  EXPECT_EQ(e.code(), "invalid_parameter");
  EXPECT_EQ(detail(e, "parameter"), "lamx");

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"model", "m"}}, c); });
  EXPECT_EQ(e.code(), "invalid_parameter");  // only classify takes a model
  EXPECT_NE(std::string(e.what()).find("only /v1/classify"), std::string::npos);

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", "4"}, {"lmax", "5"}}, c); });
  EXPECT_NE(std::string(e.what()).find("more than once"), std::string::npos);

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", "4x"}}, c); });
  EXPECT_EQ(e.category(), ErrorCategory::InvalidInput);
  EXPECT_EQ(detail(e, "value"), "4x");

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", "0"}}, c); });
  EXPECT_EQ(e.category(), ErrorCategory::InvalidInput);

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"method", "spectral"}}, c); });
  EXPECT_EQ(e.code(), "invalid_parameter");

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"include", "everything"}}, c); });
  EXPECT_EQ(e.code(), "invalid_parameter");

  e = thrown([&] { parse_compute_params(Operation::Describe, {{"reconstruction_level", "8"}}, c); });
  EXPECT_EQ(e.code(), "invalid_parameter");
}

TEST(ParseComputeParams, LimitsAreSizeProblems) {
  const ServerConfig c = config();
  EXPECT_EQ(parse_compute_params(Operation::Describe, {{"lmax", "20"}}, c).descriptor.lmax, 20);  // the limit itself is allowed
  auto e = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", "21"}}, c); });
  EXPECT_EQ(e.category(), ErrorCategory::TooLarge);
  EXPECT_EQ(detail(e, "limit"), "lmax");
  e = thrown([&] { parse_compute_params(Operation::Describe, {{"steps", "51"}}, c); });
  EXPECT_EQ(e.category(), ErrorCategory::TooLarge);
  EXPECT_EQ(detail(e, "limit"), "steps");
}

TEST(ParseComputeParams, LmaxRangeIsCoresWhateverTheConfigSays) {
  // finalize keeps max_lmax within core's range; an unfinalised config above it still cannot let past the SH fit's
  // limit, and the refusal names the bound that applied.
  ServerConfig c = config();
  c.max_lmax = kShMaxFitLmax + 100;
  EXPECT_EQ(parse_compute_params(Operation::Describe, {{"lmax", std::to_string(kShMaxFitLmax)}}, c).descriptor.lmax,
            kShMaxFitLmax);
  const auto e = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", std::to_string(kShMaxFitLmax + 1)}}, c); });
  EXPECT_EQ(e.category(), ErrorCategory::TooLarge);
  EXPECT_NE(std::string(e.what()).find("limit of " + std::to_string(kShMaxFitLmax)), std::string::npos) << e.what();
  // Below the features' minimum: a bad parameter, whatever the limit.
  const auto low = thrown([&] { parse_compute_params(Operation::Describe, {{"lmax", std::to_string(kMinFeatureLmax - 1)}}, c); });
  EXPECT_EQ(low.code(), "invalid_parameter");
}

TEST(ParseComputeParams, EveryMapMethodOfTheCoreTable) {
  // Every name of the one table parses to its method: a method added to kMapMethodNames is a parameter value.
  for (const auto& [method, name] : kMapMethodNames.entries)
    EXPECT_EQ(parse_compute_params(Operation::Describe, {{"method", name}}, config()).descriptor.method, method);
  // The refusal lists the table's names.
  const auto unknown = thrown([] { parse_compute_params(Operation::Describe, {{"method", "spectral"}}, config()); });
  EXPECT_NE(std::string(unknown.what()).find(kMapMethodNames.expected()), std::string::npos) << unknown.what();
  EXPECT_EQ(detail(unknown, "parameter"), "method");
  // A step cap for the one-solve linear map would be silently ignored: refused.
  const auto e = thrown([] { parse_compute_params(Operation::Describe, {{"method", "linear"}, {"steps", "5"}}, config()); });
  EXPECT_EQ(detail(e, "parameter"), "steps");
}

TEST(ParseComputeParams, VolumeParametersMirrorMeshLabels) {
  const ComputeParams p = parse_compute_params(
      Operation::Describe,
      {{"spacing", "0.016, 0.016,0.015"}, {"unit", "um"}, {"objects", "Components"}, {"min_voxels", "50"},
       {"drop_truncated", "TRUE"}, {"labels", "3,7, 12"}, {"threshold", "0.5"}, {"fragment_gap", "-1"},
       {"max_repair_share", "0"}},
      config());
  ASSERT_TRUE(p.volume.spacing);
  EXPECT_DOUBLE_EQ((*p.volume.spacing)[2], 0.015);
  EXPECT_EQ(p.volume.unit, "um");
  EXPECT_EQ(p.volume.objects, volume::ObjectMode::Components);
  EXPECT_EQ(p.volume.min_voxels, 50);
  EXPECT_TRUE(p.volume.drop_truncated);
  EXPECT_EQ(p.volume.label_ids, (std::vector<std::uint32_t>{3, 7, 12}));
  ASSERT_TRUE(p.volume.threshold);
  EXPECT_EQ(*p.volume.threshold, 0.5);
  EXPECT_EQ(p.volume.fragment_gap, -1);
  EXPECT_EQ(p.volume.max_repair_share, 0.0);
  EXPECT_EQ(p.volume_given.size(), 9u);
  EXPECT_TRUE(parse_compute_params(Operation::Describe, {}, config()).volume_given.empty());
}

TEST(ParseComputeParams, VolumeParameterRefusals) {
  for (const auto& [name, value] : std::vector<std::pair<std::string, std::string>>{
           {"spacing", "1,1"}, {"spacing", "1,-1,1"}, {"spacing", "1,nan,1"}, {"spacing", "1,1,1,1"},
           {"unit", "n m"}, {"unit", ""}, {"objects", "cells"}, {"min_voxels", "-3"}, {"drop_truncated", "2"},
           {"labels", "0"}, {"labels", "1,,2"}, {"labels", "-4"}, {"labels", "4294967296"}, {"threshold", "0"},
           {"threshold", "half"}, {"threshold", "inf"}, {"fragment_gap", "-2"}, {"fragment_gap", "65"},
           {"max_repair_share", "-0.1"}, {"max_repair_share", "nan"}}) {
    const auto e = thrown([&, n = name, v = value] { parse_compute_params(Operation::Describe, {{n, v}}, config()); });
    EXPECT_EQ(e.code(), "invalid_parameter") << name << "=" << value;
    EXPECT_EQ(detail(e, "parameter"), name) << value;
  }
}

TEST(SplitMultipart, FilePartsAreMeshesOtherFieldsParameters) {
  ParamMap params{{"lmax", "6"}};
  auto meshes = split_multipart({{"mesh", "a.ply", "application/octet-stream", "A"}, {"include", "", "", "mesh"},
                                 {"file_b", "", "", "B"}},
                                params, config());
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_EQ(meshes[0].filename, "a.ply");
  EXPECT_EQ(*meshes[0].bytes, "A");
  EXPECT_EQ(meshes[1].field, "file_b");
  EXPECT_EQ(params.count("include"), 1u);
  EXPECT_EQ(params.count("lmax"), 1u);
}

TEST(SplitMultipart, Refusals) {
  ParamMap params{{"lmax", "6"}};
  auto e = thrown([&] { split_multipart({{"mesh", "a", "", "A"}, {"lmax", "", "", "7"}}, params, config()); });
  EXPECT_EQ(e.code(), "invalid_parameter");  // in the query and the form
  ParamMap none;
  e = thrown([&] { split_multipart({{"lmax", "", "", "7"}}, none, config()); });
  EXPECT_EQ(e.code(), "no_mesh");
  ParamMap p3;
  e = thrown([&] { split_multipart({{"m", "1", "", "1"}, {"m", "2", "", "2"}, {"m", "3", "", "3"}}, p3, config()); });
  EXPECT_EQ(e.code(), "too_many_parts");
  EXPECT_EQ(e.category(), ErrorCategory::TooLarge);
}

TEST(RawBodyPart, RefusesFormsJsonAndEmptyBodies) {
  EXPECT_EQ(thrown([] { raw_body_part("a=b", "application/x-www-form-urlencoded; charset=utf-8"); }).code(),
            "unsupported_media_type");
  EXPECT_EQ(thrown([] { raw_body_part("{}", "Application/JSON"); }).category(), ErrorCategory::UnsupportedFormat);
  EXPECT_EQ(thrown([] { raw_body_part("", "application/octet-stream"); }).code(), "no_mesh");
  const MeshPart part = raw_body_part("OFF", "model/stl");
  EXPECT_EQ(*part.bytes, "OFF");
  EXPECT_EQ(part.content_type, "model/stl");
}

TEST(FormatHint, ParameterBeatsFileNameBeatsContentType) {
  ComputeParams p;
  MeshPart part{"mesh", "cell.OBJ", "model/stl", nullptr};
  EXPECT_EQ(format_hint(p, part), "obj");
  p.format = "off";
  EXPECT_EQ(format_hint(p, part), "off");
  ComputeParams none;
  MeshPart raw{"", "", "model/stl", nullptr};
  EXPECT_EQ(format_hint(none, raw), "model/stl");
}

}  // namespace
}  // namespace wish::server
