#include "cli/descriptor_json.hpp"

#include <string>

#include "core/common/errors.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_invariants.hpp"

namespace wish::cli {
namespace {

const char* kAxes[3] = {"x", "y", "z"};

[[noreturn]] void bad(const std::string& what) {
  throw InvalidInputError("invalid_descriptor", "invalid SH descriptor JSON: " + what);
}

}  // namespace

nlohmann::json fit_options_to_json(const ShFitOptions& o) {
  return {{"lmax", o.lmax},
          {"regularization", o.regularization},
          {"weighting", to_string(o.weighting)},
          {"solver", to_string(o.solver)},
          {"band_size", o.band_size},
          {"gram", to_string(o.gram)}};
}

nlohmann::json descriptor_to_json(const ShDescriptor& d) {
  nlohmann::json coefficients = nlohmann::json::object();
  for (int q = 0; q < 3; ++q) {
    nlohmann::json column = nlohmann::json::array();
    for (Eigen::Index j = 0; j < d.coefficients.rows(); ++j)
      column.push_back({d.coefficients(j, q).real(), d.coefficients(j, q).imag()});
    coefficients[kAxes[q]] = std::move(column);
  }
  const FitError& e = d.fit_error;
  return {{"lmax", d.lmax},
          {"options", fit_options_to_json(d.options)},
          {"index", "j = l^2 + l + m"},
          {"coefficients", std::move(coefficients)},
          {"invariants", std::vector<double>(d.invariants.data(), d.invariants.data() + d.invariants.size())},
          {"fit_error",
           {{"mean", e.mean},
            {"rms", e.rms},
            {"max", e.max},
            {"mean_relative", e.mean_relative},
            {"rms_relative", e.rms_relative},
            {"max_relative", e.max_relative}}}};
}

ShDescriptor descriptor_from_json(const nlohmann::json& json) {
  if (json.is_object() && json.contains("descriptor")) return descriptor_from_json(json["descriptor"]);
  if (!json.is_object()) bad("expected an object");
  try {
    ShDescriptor d;
    if (!json.contains("lmax") || !json["lmax"].is_number_integer()) bad("missing integer 'lmax'");
    d.lmax = json["lmax"].get<int>();
    if (d.lmax < 0 || d.lmax > kShMaxBasisLmax) bad("'lmax' out of range");
    const Eigen::Index k = sh_count(d.lmax);
    if (json.contains("options")) {
      const auto& o = json["options"];
      d.options.lmax = o.value("lmax", d.lmax);
      d.options.regularization = o.value("regularization", d.options.regularization);
      d.options.weighting = fit_weighting_from_name(o.value("weighting", std::string("area")));
      d.options.solver = fit_solver_from_name(o.value("solver", std::string("direct")));
      d.options.band_size = o.value("band_size", d.options.band_size);
      d.options.gram = gram_method_from_name(o.value("gram", std::string("quadrature")));
    } else {
      d.options.lmax = d.lmax;
    }
    if (!json.contains("coefficients") || !json["coefficients"].is_object()) bad("missing object 'coefficients'");
    d.coefficients.resize(k, 3);
    for (int q = 0; q < 3; ++q) {
      const auto& col = json["coefficients"].value(kAxes[q], nlohmann::json());
      if (!col.is_array() || Eigen::Index(col.size()) != k)
        bad(std::string("'coefficients.") + kAxes[q] + "' must hold (lmax+1)^2 = " + std::to_string(k) + " pairs");
      for (Eigen::Index j = 0; j < k; ++j) {
        const auto& pair = col[size_t(j)];
        if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
          bad(std::string("'coefficients.") + kAxes[q] + "[" + std::to_string(j) + "]' is not [re, im]");
        d.coefficients(j, q) = {pair[0].get<double>(), pair[1].get<double>()};
      }
    }
    d.invariants = sh_invariants(d.coefficients);  // recomputed: always consistent with the coefficients
    if (json.contains("fit_error")) {
      const auto& e = json["fit_error"];
      d.fit_error.mean = e.value("mean", 0.0);
      d.fit_error.rms = e.value("rms", 0.0);
      d.fit_error.max = e.value("max", 0.0);
      d.fit_error.mean_relative = e.value("mean_relative", 0.0);
      d.fit_error.rms_relative = e.value("rms_relative", 0.0);
      d.fit_error.max_relative = e.value("max_relative", 0.0);
    }
    return d;
  } catch (const nlohmann::json::exception& e) {
    bad(e.what());
  }
}

}  // namespace wish::cli
