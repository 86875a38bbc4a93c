#pragma once
// The enums of the sphere-map stage and their wire names, one table per enum (enum_names.hpp), in one Eigen-free
// header that every file of core/spherical_map and every caller (CLI flags, request parsing, model files, the
// OpenAPI lists) can include without pulling in the numerics — the layout of ceres-solver's types.h.
// A name printed by to_string is the name parsed by *_from_name: both read the same table.

#include <string>

#include "core/common/enum_names.hpp"

namespace wish {

// The recipe's map method (docs/design/spherical-map.md §3, §8.1, §8.2; progressive_embedding.hpp): the first attempt of the
// chain (map_chain.hpp).
enum class MapMethod { Willmore, Cmcf, Linear, Progressive };
inline constexpr EnumNames<MapMethod, 4> kMapMethodNames{{{
    {MapMethod::Willmore, "willmore"},
    {MapMethod::Cmcf, "cmcf"},
    {MapMethod::Linear, "linear"},
    {MapMethod::Progressive, "progressive"}}}};
// A method that is not a flow (one shot, bijective by construction): it runs without an Ok map whatever the time
// budget (bijectivity before time), and its map's repair may use the whole chain budget.
constexpr bool is_one_shot(MapMethod method) { return method == MapMethod::Linear || method == MapMethod::Progressive; }
const char* to_string(MapMethod method);
MapMethod map_method_from_name(const std::string& name);  // throws InvalidInputError

// The sparse Cholesky behind every solve of the stage.
enum class LinearSolverKind { Cholmod, EigenSimplicial };
inline constexpr EnumNames<LinearSolverKind, 2> kLinearSolverNames{{{
    {LinearSolverKind::Cholmod, "cholmod"},
    {LinearSolverKind::EigenSimplicial, "eigen_simplicial"}}}};
const char* to_string(LinearSolverKind solver);
LinearSolverKind linear_solver_from_name(const std::string& name);  // throws InvalidInputError

// Why a map or a flow failed (None prints as "").
enum class MapCheck {
  None, NonFinite, FlippedFaces, DegenerateFaces, Degree, ConformalDistortion, Roundness, Energy, EigenResidual,
  Solver, Mobius, TimeBudget
};
inline constexpr EnumNames<MapCheck, 12> kMapCheckNames{{{
    {MapCheck::None, ""},
    {MapCheck::NonFinite, "non_finite"},
    {MapCheck::FlippedFaces, "flipped_faces"},
    {MapCheck::DegenerateFaces, "degenerate_faces"},
    {MapCheck::Degree, "degree"},
    {MapCheck::ConformalDistortion, "conformal_distortion"},
    {MapCheck::Roundness, "roundness"},
    {MapCheck::Energy, "energy"},
    {MapCheck::EigenResidual, "eigen_residual"},
    {MapCheck::Solver, "solver"},
    {MapCheck::Mobius, "mobius"},
    {MapCheck::TimeBudget, "time_budget"}}}};
const char* to_string(MapCheck check);

// Why a flow stopped: "converged" (roundness tolerance), "energy_plateau", "roundness_plateau", "energy_stall" (no
// step down to min_tau lowers E), "step_cap", "rejected_steps" (τ fell below min_tau for another reason),
// "solver_failed", "non_finite", "time_budget", or "none" (a one-shot method: the linear map).
enum class FlowStop {
  None, Converged, EnergyPlateau, RoundnessPlateau, EnergyStall, StepCap, RejectedSteps, SolverFailed, NonFinite,
  TimeBudget
};
inline constexpr EnumNames<FlowStop, 10> kFlowStopNames{{{
    {FlowStop::None, "none"},
    {FlowStop::Converged, "converged"},
    {FlowStop::EnergyPlateau, "energy_plateau"},
    {FlowStop::RoundnessPlateau, "roundness_plateau"},
    {FlowStop::EnergyStall, "energy_stall"},
    {FlowStop::StepCap, "step_cap"},
    {FlowStop::RejectedSteps, "rejected_steps"},
    {FlowStop::SolverFailed, "solver_failed"},
    {FlowStop::NonFinite, "non_finite"},
    {FlowStop::TimeBudget, "time_budget"}}}};
const char* to_string(FlowStop stop);

// Distortion verdict of a map: "good" (K p99 within max_conformal_p99), "distorted" (bijective, above it: still a
// usable descriptor, reported rather than refused unless strict_conformal_bound), "failed" (not bijective).
enum class MapVerdict { Good, Distorted, Failed };
inline constexpr EnumNames<MapVerdict, 3> kMapVerdictNames{{{
    {MapVerdict::Good, "good"},
    {MapVerdict::Distorted, "distorted"},
    {MapVerdict::Failed, "failed"}}}};
const char* to_string(MapVerdict verdict);

// Outcome of one attempt (and of the chain: the returned attempt's).
enum class MapStatus { Ok, NotConverged, VerificationFailed, SolverFailed };
inline constexpr EnumNames<MapStatus, 4> kMapStatusNames{{{
    {MapStatus::Ok, "ok"},
    {MapStatus::NotConverged, "not_converged"},
    {MapStatus::VerificationFailed, "verification_failed"},
    {MapStatus::SolverFailed, "solver_failed"}}}};
const char* to_string(MapStatus status);

}  // namespace wish
