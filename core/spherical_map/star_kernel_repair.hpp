#pragma once
// Exact local repair of a sphere map's bad faces, one vertex at a time: move a vertex of a bad face into the KERNEL
// of its one-ring on the sphere — the points y with det(y, a, b) > 0 for every link edge (a, b), i.e. exactly the
// positions where every face of its star passes the verification's flip test (map_verification.hpp). Each condition
// is a great-circle half-space, so the kernel is a convex polygon in the gnomonic chart (central projection maps
// great circles to lines) and is computed exactly by clipping (one_ring_kernel_centroid, progressive_embedding.hpp;
// the placement step of Praun & Hoppe 2003's progressive embedding). The vertex moves along the great circle from
// its position towards the kernel's centroid, halfway into the kernel past where it enters it: the least move with a
// margin. Only its own star changes, and a good face of that star stays good (the kernel is where all of them are),
// so every move removes bad faces and adds none.
//
// Why (docs/design/needle-flows.md): the flips the flows leave on decimated, needle-heavy meshes are mostly slivers
// with an input angle of 150–180° whose image spans 10–60° of the sphere; the chord test then depends on which side
// of the GREAT circle through the two far corners the obtuse corner lands, which the straight lines of a
// stereographic chart (chart_untangle.hpp, convex_combination_repair.hpp) do not see. The kernel test is exact.
// A vertex whose kernel is empty (a tangled neighbourhood) is left for its neighbours' moves in the next round.

#include <vector>

#include <Eigen/Core>

#include "core/common/cpu_budget.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {

struct StarKernelRepairOptions {
  int max_rounds = 20;  // rounds over the vertices of the bad faces left
  // Where in the kernel a vertex of a bad face goes: this fraction of the way from where its path enters the kernel
  // to the kernel's centroid (0: on the kernel's edge, 1: its centroid). The least move first (the map stays as it
  // was as far as it can); when that leaves bad faces, the whole repair is redone from the input map with the next
  // margin: a vertex placed deeper in its kernel leaves its neighbours' kernels larger (measured on the generated
  // needle spines, docs/design/needle-flows.md: 0.2 alone leaves a tangle on one spine, 0.5 alone on another).
  std::vector<double> margins = {0.2, 0.5};
  int max_rings = 3;    // neighbours moved within their kernels when a round stalls (see place_in_star_kernels)
  // A map with more bad faces than this share is a failed flow, not a few flips: left as it is (measured: the needle
  // retry leaves 0.2-3.6 % on the generated needle spines, which this repairs, and 26 % on nmv_spine_4 / 25, where
  // trying cost 0.12-0.17 CPU s and fixed nothing).
  double max_bad_fraction = 0.05;
};

struct StarKernelRepairResult {
  long bad_faces_before = 0, bad_faces_after = 0;
  long moves = 0;           // vertex placements made (in the pass kept)
  long moved_vertices = 0;  // distinct vertices moved (in the pass kept)
  double margin = 0;        // the margin of the pass kept
  bool budget_stopped = false;  // the CPU budget ran out (checked before each round)
};

// `rings[v]`: the one-ring of v in counter-clockwise order seen from outside (face (v, a, b) has a before b).
// Moves vertices of `sphere` in place (every move keeps or lowers the number of bad faces); keeps the first pass
// (by options.margins) that leaves no bad face, else the one that leaves the fewest.
StarKernelRepairResult place_in_star_kernels(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3i& faces,
                                             const std::vector<std::vector<int>>& rings,
                                             const MapVerificationThresholds& thresholds,
                                             const StarKernelRepairOptions& options = {},
                                             const CpuBudget& budget = {});

}  // namespace wish::spherical
