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
// (plateau, also a stop), R falls by less than roundness_stall of itself (R plateau, also a stop), no step down to
// min_tau lowers the energy (stall, also a stop: status Ok, FlowStop::EnergyStall; the map is accepted only if it
// verifies), or at max_steps (NotConverged, failed_check "roundness", hit_step_cap).
// Symbolic factorisations (Dirac, pinned L, filter) are done once per call, with the context's METIS ordering;
// numeric ones once per step.

#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {

struct WillmoreOptions {
  double tau = 0.95;                 // dimensionless step: rho = -tau * P(H) (docs/design/spherical-map.md §3)
  int max_steps = 20;                // step cap (the paper uses 10 on nuclei)
  double roundness_tolerance = 2e-3; // stop when std(r)/mean(r) falls below
  // ... or when the relative energy decrease per step falls below (a stalled flow: the map is then accepted if it
  // verifies — bijective, bounded distortion — whatever the roundness; coarse meshes plateau at R ~ 1e-2).
  // A step whose energy rises for every tau down to min_tau is the same kind of stall.
  double energy_tolerance = 1e-4;
  // Added: ... or when the roundness falls by less than this fraction in a step (R plateau). A healthy flow halves R
  // per step (docs/design/spherical-map.md §9); on coarse or staircase meshes R levels off at ~1e-2 while the energy keeps
  // creeping down by ~0.5 %/step and K slowly drifts (cf. the peanut in §9: "stop early rather than iterating
  // long"). Same treatment as an energy plateau: a stop, judged by verification. Only while the energy also falls
  // by less than roundness_stall_energy per step: an R that stalls or rises while E still drops fast (homer, spool:
  // −20…−80 %/step) is the flow reshaping the surface, not a plateau.
  double roundness_stall = 0.05;
  double roundness_stall_energy = 0.05;
  double min_tau = 0.05;             // step rejection halves tau down to this, then gives up
  bool filtered = false;             // low-pass filtered flow for noisy segmentation meshes
  double filter_strength = 2.0;      // sigma = filter_strength * (mean edge length)^2
  int max_inverse_iterations = 5;    // inverse power iteration for the smallest eigenvector
  // Added: an eigen-solve whose relative residual stays above this after max_inverse_iterations rejects the step.
  double max_eigen_residual = 1e-4;
  double energy_increase_tolerance = 1e-3;  // reject a step raising E_W by more than this fraction
  // Added: solve the Dirac eigenproblem in its complex Hermitian 2V×2V form (same λ, ~2× fewer Cholesky flops)
  // instead of the real symmetric 4V×4V form (docs/design/spherical-map.md §4, §9).
  bool complex_dirac = true;
  // The needle operator (issue 24 item 3; docs/design/needle-flows.md): H, the mass and the roundness from the
  // intrinsic Delaunay operator of the current surface (nonnegative weights on needle triangles), and the Poisson
  // step as a true weighted least-squares fit of the transformed edges — the mollified cotan weights of the mesh's
  // own triangles clamped to >= 0. Not a recipe field: only the chain's needle retry sets it (map_chain.cpp).
  bool needle_operator = false;
  bool operator==(const WillmoreOptions&) const = default;
};

namespace spherical {

// control.start: continue a flowed surface (e.g. of an earlier attempt that ran out of steps — saves re-running
// those steps). The operator behind L, M and the Poisson step is the context's laplacian() kind, except that
// intrinsic Delaunay is replaced by the mollified operator on the mesh's own triangles (see the .cpp).
FlowResult willmore_flow(const MapContext& context, const WillmoreOptions& options, const FlowControl& control = {});

}  // namespace spherical
}  // namespace wish
