#pragma once
// Conformal map of a closed genus-0 mesh onto the unit sphere (paper §4; docs/design/spherical-map.md): the
// facade of core/spherical_map. Entry point: compute_spherical_map(). Methods: discrete Willmore flow in curvature
// space with spin transformations (Crane, Pinkall, Schröder 2013; willmore_flow.hpp), conformalized mean curvature
// flow (Kazhdan et al. 2012; cmcf.hpp) and the linear puncture/harmonic/stereographic method (FLASH, Choi et al.
// 2015; bijective by construction; linear_map.hpp).
// Every map is projected to the sphere, Möbius-normalised (area-centre balancing with input vertex areas as
// weights) and verified (map_attempt.hpp); a map that fails verification is never reported as Ok. With `fallback`,
// a failed attempt is followed by the chain of docs/design/spherical-map.md §7 (map_chain.hpp: more steps → cMCF → linear
// method), stopping at the first Ok attempt that is final; every attempt is recorded, and the returned map is the
// least distorted Ok attempt or, when none is Ok, the least-bad one (see SphericalMapResult).
//
// Layout, bottom up: map_types.hpp (enums and their names, Eigen-free) → flow_result.hpp, map_context.hpp (what an
// attempt shares, built once per mesh) → one file per method with its options → map_verification, the repairs →
// map_options.hpp (SphericalMapOptions) → map_attempt → map_chain → this facade.
//
// Preconditions: the mesh passed prepare_for_mapping() (closed, manifold, one component, genus 0, outward).

#include <vector>

#include <Eigen/Core>

#include "core/common/deadline.hpp"
#include "core/geometry/intrinsic_laplacian.hpp"
#include "core/mesh/mesh.hpp"
#include "core/spherical_map/density_equalizing.hpp"
#include "core/spherical_map/flow_result.hpp"
#include "core/spherical_map/map_attempt.hpp"
#include "core/spherical_map/map_chain.hpp"
#include "core/spherical_map/map_options.hpp"
#include "core/spherical_map/map_types.hpp"
#include "core/spherical_map/map_verification.hpp"

namespace wish {

struct SphericalMapResult {
  Eigen::MatrixX3d sphere;           // #V by 3 unit vectors: the image of each input vertex
  MapStatus status = MapStatus::Ok;  // of the attempt whose map is returned
  MapCheck failed_check = MapCheck::None;
  MapVerdict verdict = MapVerdict::Failed;  // Added: quality.verdict of the returned map
  MapQuality quality;
  MapMethod method_used = MapMethod::Willmore;
  // In order. `sphere` is the map of attempts[chosen_attempt]: the Ok attempt of lowest K p99 (the chain stops at
  // the first Ok attempt that is not a repaired, distorted one), or,
  // when none is Ok, the least-bad one — a verified map of a not-converged flow first (lowest K p99), else the one
  // with the fewest non-finite, flipped and degenerate faces — with that attempt's (not Ok) status.
  std::vector<MapAttempt> attempts;
  int chosen_attempt = 0;            // Added
  // Added: the operator of the returned map's attempt (mollification epsilon, zero-area faces, negative weights
  // before, flips done).
  geometry::IntrinsicStats operator_stats;
  // Added: planned attempts of the chain that did not run because the flow budget was spent, in plan order; the
  // running flow's own stop is its attempt's FlowStop::TimeBudget, a repair's stop its attempt's
  // repair_budget_stopped. Empty when the budget stopped nothing.
  std::vector<MapAttemptPlan> skipped_for_budget;
  // Added: the area-aware correction of the returned map (stop NotRun when options.area_correction is none or the
  // map is not Ok).
  AreaCorrectionReport area_correction;
  // Added (issue 37): the relaxation to the canonical map (stop NotRun when options.canonical.method is None or the
  // chain's map is not Ok). `sphere` and `quality` then describe the canonical map; method_used and the attempts
  // still say which attempt made its start.
  CanonicalMapReport canonical;
  double seconds = 0;
  double cpu_seconds = 0;            // Added: CPU seconds of the calling thread for the whole chain
  bool ok() const { return status == MapStatus::Ok; }
};

// Never throws for numerical trouble (that is a status); throws TimeoutError when `deadline` passes
// between flow steps, and InvalidInputError for meshes that violate the preconditions.
SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options = {},
                                         const Deadline& deadline = {});

}  // namespace wish
