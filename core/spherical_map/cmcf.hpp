#pragma once
// Conformalized mean curvature flow (Kazhdan, Solomon, Ben-Chen 2012; docs/design/spherical-map.md §8.1).
// Semi-implicit MCF with the stiffness frozen at the input:  (M_t + δ L₀) x_{t+1} = M_t x_t,
// L₀ = PSD cot Laplacian of the (area-4π normalised) input, M_t = lumped mass of the current surface; after each
// step centre on the area-weighted centroid and rescale to area 4π. δ is in units of area at total area 4π
// (δ ≈ 1 ⇔ δ ≈ A/4π for the raw mesh). Stops when roundness < roundness_tolerance (Ok), when the best R has not
// fallen by roundness_stall of itself for stall_patience steps (stalled, Ok with "stalled" in the message: judged by
// verification), or at max_steps (NotConverged, failed_check "roundness", hit_step_cap). Where it stops short of
// convergence it returns its ROUNDEST surface: on elongated shapes R is not monotone (measured on UroCell
// mitochondria: 0.43 → 0.14, a plateau of ~10 steps, then 0.02; or 0.02 → 0.40 when thin parts pinch).
// One V×V factorisation per step; symbolic analysis once.

#include "core/common/cpu_budget.hpp"
#include "core/common/deadline.hpp"
#include "core/mesh/mesh.hpp"
#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace wish::spherical {

// `laplacian`: the operator behind L₀ and M_t (intrinsic_laplacian.hpp). `start` (optional): flowed positions to
// continue from (input connectivity), e.g. the surface of an earlier attempt that hit its step cap; L₀ stays the
// input's, so a continued flow is the same flow run longer.
FlowResult cmcf_flow(const Mesh& mesh, const CmcfOptions& options, LinearSolverKind solver,
                     const geometry::IntrinsicOptions& laplacian = {}, const Deadline& deadline = {},
                     const CpuBudget& budget = {}, const Eigen::MatrixX3d* start = nullptr);  // budget: soft CPU-time limit (cpu_budget.hpp), stops with FlowStop::TimeBudget

}  // namespace wish::spherical
