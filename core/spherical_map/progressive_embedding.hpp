#pragma once
// Progressive spherical embedding: a map whose bijectivity does not depend on a flow converging or on the shape's
// conformal area compression (Praun & Hoppe 2003, "Spherical parametrization and remeshing",
// ACM TOG 22(3), §3: coarse-to-fine embedding through a progressive mesh; the kernel argument is theirs, the
// relaxation below replaces their stretch optimisation).
//  1. Simplify the mesh by half-edge collapses (shortest edge first) down to a tetrahedron. A collapse v → u is
//     taken only when it passes the link condition (the common neighbours of u and v are exactly the two vertices
//     opposite the edge; Dey, Edelsbrunner, Guha, Nekhayev 1999), so every intermediate mesh is a closed manifold
//     genus-0 triangulation; every such triangulation with more than 4 vertices has a contractible edge (Steinitz),
//     so the simplification always reaches 4 vertices.
//  2. Embed the tetrahedron as the regular one inscribed in the unit sphere, oriented like the mesh.
//  3. Undo the collapses in reverse order (vertex splits). A split of u re-inserts v inside the spherical kernel of
//     its one-ring (the intersection of the hemispheres left of its link edges): the kernel is never empty — points
//     close to u in the bisector of the sector that v's faces took from u's star see every link edge (Praun &
//     Hoppe's argument) — and every face that does not contain v existed, positively oriented, before the split.
//     v goes to the average of its neighbours when that point is in the kernel, else to the best of a set of
//     candidates around u.
//  4. Each time the vertex count has grown by `level_growth`, and at the end, relax: Gauss–Seidel sweeps moving
//     every vertex toward the average of its neighbours (uniform spherical Tutte weights: equal sphere area per
//     vertex, so a thin tube keeps a share of the sphere proportional to its vertex count — no exponential
//     compression), each move shortened until all faces of the vertex stay positively oriented with height at
//     least min_height; then Möbius balancing with uniform weights, kept only when it leaves every face valid
//     (it stops the slow drift of iterative spherical averaging toward a point; Gotsman, Gu, Sheffer 2003).
// Every accepted state is a map with every chord triangle positively oriented and no height below min_height;
// the chain verifies the result as for every method, without its Möbius balancing by input areas
// (FlowResult::keep_normalisation). Cost O(V log V) plus the sweeps (linear in V per sweep).
// Status: a recipe method of its own (`--method progressive`), not yet the last resort of the other chains
// (map_chain.cpp): on a decimated 9,306-vertex spine and on camel (9,770) no kernel candidate keeps min_height
// at 2,627 and 7,256 vertices (the chain then falls back to the linear map), and
// on decimated spines the uniform weights leave an area distortion of ~1e6 (coil: 2.3; tests/spherical_map/
// progressive_embedding_test.cpp).

#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {

struct ProgressiveOptions {
  double level_growth = 1.25;   // relax whenever the vertex count has grown by this factor
  int sweeps_per_level = 4;     // Gauss–Seidel sweeps per level
  int final_sweeps = 40;        // ... and on the whole mesh at the end
  // Smallest chord-triangle height 2·area/longest edge (unit sphere) a move may leave: well above the
  // verification's degenerate_height (1e-14), so one more rounding cannot flip a face.
  double min_height = 1e-12;
  bool operator==(const ProgressiveOptions&) const = default;
};

namespace spherical {

// Result: vertices on the unit sphere (on_sphere = true), one step record, status Ok, or SolverFailed with
// failed_check "solver" when the simplification stalls or a vertex finds no kernel point in double precision
// (neither is expected: the message then says which vertex). control.deadline is checked between levels; the
// CPU budget is not used (a last resort runs to its end).
FlowResult progressive_map(const MapContext& context, const ProgressiveOptions& options, const FlowControl& control = {});

}  // namespace spherical
}  // namespace wish
