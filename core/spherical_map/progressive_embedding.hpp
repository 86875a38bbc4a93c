#pragma once
// Progressive spherical embedding: a map whose bijectivity does not depend on a flow converging or on the shape's
// conformal area compression (Praun & Hoppe 2003, "Spherical parametrization and remeshing", ACM TOG 22(3), §3:
// coarse-to-fine embedding through a progressive mesh, each vertex split placed in its one-ring's kernel, the
// L2 stretch of Sander et al. 2001 lowered as the vertices come back). The last resort of every chain
// (map_chain.cpp plan_attempts) and a recipe method of its own (`--method progressive`).
//  1. Simplify the mesh by half-edge collapses (shortest edge first) down to a tetrahedron. A collapse v → u is
//     taken only when it passes the link condition (the common neighbours of u and v are exactly the two vertices
//     opposite the edge; Dey, Edelsbrunner, Guha, Nekhayev 1999), so every intermediate mesh is a closed manifold
//     genus-0 triangulation; every such triangulation with more than 4 vertices has a contractible edge (Steinitz),
//     so the simplification always reaches 4 vertices.
//  2. Embed the tetrahedron as the regular one inscribed in the unit sphere, oriented like the mesh.
//  3. Undo the collapses in reverse order (vertex splits). A split of u re-inserts v at the centroid of the
//     kernel of its one-ring, computed exactly as a convex polygon by half-plane clipping in the gnomonic chart
//     about u (great circles are straight lines there). The kernel is never empty — points close to u in the
//     sector that v's faces took from u's star see every link edge (Praun & Hoppe's argument) — and every face
//     that does not contain v existed, positively oriented, before the split. Should the kernel be too thin for
//     the height margin in double precision, u's neighbourhood is spread first (v collapsed back) and the split
//     tried again. v and u are then moved down the stretch energy.
//     A third embedding runs only when both spreadings below fail or leave a face far below its area share
//     (ProgressiveOptions::pair_placement_below_area_ratio): each split places u and v TOGETHER in the kernel of
//     u's star before the split, on either side of its centroid (every face with a corner on the old link stays
//     valid; only the two restored faces depend on the pair). v alone in its own kernel sits in a thin wedge at u
//     when v's faces took a thin sector of u's star, and the two restored faces become slivers (measured on the
//     3-turn coil: sphere area 1e-7 against a surface share 1e-1 at 72 vertices, never undone by later moves; on
//     the 12-turn coil with wire 1/20 such crowding made a placement fail at any margin).
//  4. Each time the vertex count has grown by `level_growth`, and at the end, Gauss–Seidel sweeps of stretch
//     descent over all vertices. The stretch of the map sphere → surface grows without bound when a sphere triangle
//     shrinks relative to its surface triangle, so thin parts (a coil's middle, a spine's neck) keep a sphere area
//     close to their surface share instead of the exponential compression of conformal or uniform-Tutte maps.
//     Every move is a line search step taken only when all faces of the moved vertex stay positively oriented
//     with height at least min_height.
// Every accepted state is a map with every chord triangle positively oriented and no height below min_height (or,
// after a placement that needed the last retries, 3 % of it: still 3× the verification's degenerate_height);
// the chain verifies the result as for every method, without its Möbius balancing by input areas
// (FlowResult::keep_normalisation: the stretch minimum is not Möbius-invariant, balancing would only raise it).
// Cost O(V log V) for the simplification plus the sweeps (linear in V per sweep; the level sweeps sum to a
// geometric series, about sweeps_per_level · V / (1 − 1/level_growth) vertex moves).

#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_context.hpp"

namespace wish {

struct ProgressiveOptions {
  double level_growth = 1.25;   // relax whenever the vertex count has grown by this factor
  int sweeps_per_level = 4;     // Gauss–Seidel sweeps per level
  int final_sweeps = 40;        // ... and on the whole mesh at the end
  // A sweep that lowers the stretch energy by less than this share of it ends the level's (or the final) sweeps.
  double sweep_tolerance = 1e-3;
  // Smallest chord-triangle height 2·area/longest edge (unit sphere) a move may leave: well above the
  // verification's degenerate_height (1e-14), so one more rounding cannot flip a face.
  double min_height = 1e-12;
  // When the kept embedding's most compressed face has a sphere area share below this fraction of its surface
  // share (or both embeddings fail), a third embedding places each split's pair in u's old kernel (step 3) and is
  // kept if its most compressed face is less compressed.
  double pair_placement_below_area_ratio = 1e-9;
  // The uniform spreading is given up when its placements need more than this many neighbourhood spreads (0: no
  // limit). A spread means a kernel thinner than min_height: the uniform (Tutte-like) spreading compresses a thin
  // part exponentially, and such an embedding was never the one kept (measured over ../shared/data, the UroCell and
  // generated shapes, docs/benchmarks.md: every uniform embedding that needed a spread — 1 to 2,446 of them — lost
  // to the stretch spreading or the pair placement, while its spreads took up to 1.9 CPU s on the fine 6-turn
  // coil). Should no other embedding succeed, it runs again without the limit.
  int uniform_max_spreads = 8;
  bool operator==(const ProgressiveOptions&) const = default;
};

namespace spherical {

// Result: vertices on the unit sphere (on_sphere = true), one step record, status Ok, or SolverFailed with
// failed_check "solver" when the simplification stalls or a vertex finds no kernel point in double precision
// (neither is expected: the message then says which vertex). control.deadline is checked between levels; the
// CPU budget is not used (a last resort runs to its end).
FlowResult progressive_map(const MapContext& context, const ProgressiveOptions& options, const FlowControl& control = {});

// The placement step of a vertex split: the centroid of the kernel of a one-ring on the unit sphere, i.e. of the
// points y that see every link edge (a, b) from the left, det(y, a, b) > 0 (`link`: the edges (a, b) of the faces
// (v, a, b) of the star, any order). Computed exactly as a convex polygon in the gnomonic chart about the sphere
// point c — central projection onto the tangent plane at c maps great circles to lines, so each condition is a
// half-plane — by clipping a square about c (Sutherland & Hodgman 1974), within the hemisphere about c; c should
// lie in the kernel or on its boundary. nullopt when the clipped polygon has no area in double precision.
std::optional<Eigen::Vector3d> one_ring_kernel_centroid(
    const Eigen::Vector3d& c, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& link);

}  // namespace spherical
}  // namespace wish
