#pragma once
// Local repair of a sphere map that is bijective except for a few faces (docs/design/spherical-map.md §7 "always finish with
// the flip check"). Conformal maps preserve angles, so an input triangle with an angle near 180° keeps it on the
// sphere; its circumcircle is then so large that the FLAT chord triangle faces the origin (a flip by the
// verification test, although the curved image is fine), and long protrusions are compressed to heights at the
// limit of double precision (numerically degenerate faces). Both are local: a handful of faces out of thousands.
// The repair relaxes only the vertices of those faces and a few rings around them by Gauss–Seidel sweeps of
//   u_i ← normalise(Σ_{j ∈ N(i)} u_j)        (uniform weights)
// — the spherical Tutte embedding of a small patch with its outer ring fixed: positive weights give a flip-free
// disk embedding for a patch that is nearly planar (Tutte 1963; Floater 2003), and uniform weights equalise the
// triangle shapes, so needles and compressed slivers open up. The patch grows by one ring per round while bad
// faces remain, up to max_fraction of the vertices. The map elsewhere is untouched; the caller re-verifies
// everything (the repair is never trusted by itself) and reports the number of moved vertices.
// Bounded by `budget` (the map chain's CPU budget, issue 11): checked before every sweep; when it is spent the
// relaxation stops, the map is left as it was and budget_stopped is set (the caller's verification then fails
// the map on its remaining flips: a map with flips is never accepted).

#include <Eigen/Core>

#include "core/common/cpu_budget.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {

struct UntangleOptions {
  int rings = 2;               // initial patch: bad faces' vertices plus this many rings
  int max_rounds = 12;         // grow the patch by one ring per round
  int sweeps = 40;             // Gauss–Seidel sweeps per round: at least this, up to the patch size ...
  int max_sweeps = 400;        // ... capped here
  double max_fraction = 0.05;  // give up when the patch would exceed this fraction of the vertices ...
  int min_patch = 150;         // ... or this many vertices, whichever is larger (small meshes)
};

struct UntangleResult {
  long bad_faces_before = 0, bad_faces_after = 0;  // flipped or numerically degenerate
  long moved_vertices = 0;
  bool budget_stopped = false;  // the CPU budget ran out before the bad faces were gone (map left unchanged)
};

// `sphere` (V×3 unit vectors) is modified in place only where the patch is relaxed.
UntangleResult untangle_sphere_map(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
                                   const MapVerificationThresholds& thresholds, const UntangleOptions& options = {},
                                   const CpuBudget& budget = {});

}  // namespace wish::spherical
