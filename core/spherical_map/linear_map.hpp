#pragma once
// Linear conformal sphere map: puncture + harmonic map to a triangle + inverse stereographic projection
// (FLASH, Choi, Lam & Lui 2015, steps 1–3; docs/design/spherical-map.md §8.2). The last fallback of the chain (§7): two sparse
// V×V solves, and — unlike the flows — bijective BY CONSTRUCTION:
//  1. Puncture the "big triangle" T = (a, b, c), the most equilateral face (smallest max-edge/min-edge ratio); the
//     rest of the mesh is a disk bounded by a → c → b.
//  2. Pin a, b, c at a planar triangle similar to T (clockwise, so that the disk's faces come out CCW) and solve
//     the discrete Laplace equation L_II z_I = −L_IB z_B (two real right-hand sides) with the cot weights of the
//     mesh without T — the most conformal choice. Cot weights can be negative (obtuse meshes), and then the
//     harmonic map may fold; if any planar face comes out inverted (or the system is not definite), the solve is
//     repeated with the weights CLAMPED from below to a small positive value (LinearMapOptions::min_weight). With
//     every interior edge weight positive and a convex boundary polygon, Tutte's theorem in Floater's form
//     ("One-to-one piecewise linear mappings over triangulations", Math. Comp. 2003) guarantees that the planar
//     map is an embedding: no flipped and no collapsed triangle (in exact arithmetic). Clamping costs
//     conformality (cigar 1:0.35: K̄ 1.2 → 2.2), which is why it is only the second choice.
//  3. Translate the plane so that the boundary triangle's circumcentre is at 0, scale so the median |z| is 1,
//     and map to S² by the inverse stereographic projection u = (2x, 2y, 1 − |z|²)/(1 + |z|²), which is
//     conformal and orientation-preserving (0 ↦ north pole); T becomes the cap around the south pole (∞), which
//     is smaller than a hemisphere because the circumradius exceeds max |z| ≥ 1.
// FLASH's step 4 (Beltrami correction of the distortion near T) is not implemented: K_max ≈ 2–2.5 near T
// (docs/design/spherical-map.md §9). The caller Möbius-balances and verifies as for the flows; verification is still needed
// because exponentially compressed regions can meet the limits of double precision.

#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {

struct LinearMapOptions {
  // Cot weights below min_weight × mean |w| are raised to it: all weights positive ⇒ Tutte/Floater embedding.
  double min_weight = 1e-3;
  // Use the clamped weights even when the plain cot map is a planar embedding (the chain's second linear attempt:
  // a plain map can still fail on the sphere, e.g. near-180° angles whose flat chord triangles face the origin).
  bool always_clamp = false;
  bool operator==(const LinearMapOptions&) const = default;
};

namespace spherical {

// The operator is the context's input_operator(). Result: vertices on the unit sphere (on_sphere = true), one step
// record with the timings, clamped_weights, status Ok or SolverFailed ("solver", "non_finite"). A one-shot method:
// control's budget and start are not used.
FlowResult linear_map(const MapContext& context, const LinearMapOptions& options, const FlowControl& control = {});

}  // namespace spherical
}  // namespace wish
