#pragma once
// Discrete Willmore flow in curvature space with spin transformations (Crane, Pinkall, Schröder 2013, "Robust
// Fairing via Conformal Curvature Flow"; docs/design/spherical-map.md §1–5). One step, relative to the current surface:
//   normals N, cot Laplacian L (PSD), lumped mass M, mean curvature H_i = N_i·(Lx)_i/(2M_i)  (H > 0 convex)
//   → admissible projection P (⟨,⟩_M-orthogonal to {1, N_x, N_y, N_z})
//   → curvature change ρ = −τ P(H)  (or −τ P(H_σ), H_σ = (M + σL)⁻¹ M H, for the filtered flow)
//   → Dirac matrix 𝔼(ρ) (4V×4V, symmetric PSD), λ = smallest eigenvector (shifted inverse iteration)
//   → transformed edges ẽ, divergence ω, pinned Poisson solve L x̃ = ω
//   → centre on the area-weighted centroid, scale to area 4π.
// A step is rejected (τ halved, down to min_tau) if the energy rises by more than energy_increase_tolerance, the
// eigen-residual stays above max_eigen_residual, or anything turns non-finite. The flow stops when the roundness
// falls below roundness_tolerance (converged), the relative energy decrease falls below energy_tolerance
// (plateau, also a stop), R falls by less than roundness_stall of itself (R plateau, also a stop), no step down to min_tau lowers the energy (stall, also a stop; a stall is status Ok with
// "stalled" in the message: the map is accepted only if it verifies), or at max_steps (NotConverged, failed_check
// "roundness", hit_step_cap).
// Symbolic factorisations (Dirac, pinned L, filter) are done once per call; numeric ones once per step.

#include "core/common/cpu_budget.hpp"
#include "core/common/deadline.hpp"
#include "core/mesh/mesh.hpp"
#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish::spherical {

// `start` (optional): flowed positions to continue from (input connectivity), e.g. the surface of an earlier
// attempt that ran out of steps ("more steps" in the fallback chain) — saves re-running those steps.
// `budget`: soft limit of this thread's CPU time (cpu_budget.hpp; the flow stops with FlowStop::TimeBudget, keeping its surface); `laplacian`: the operator behind L, M and the Poisson step (intrinsic_laplacian.hpp).
FlowResult willmore_flow(const Mesh& mesh, const WillmoreOptions& options, LinearSolverKind solver,
                         const geometry::IntrinsicOptions& laplacian = {}, const Deadline& deadline = {},
                         const Eigen::MatrixX3d* start = nullptr, const CpuBudget& budget = {});

}  // namespace wish::spherical
