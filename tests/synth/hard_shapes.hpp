#pragma once
// Hard closed genus-0 shapes for the map tests and benchmarks (issue 24 item 4), made in the test tree, never bundled:
// coils (3–12 turns, wire radius down to 1/20 of the coil radius), dumbbells (neck down to 1:20 of the bulbs), an
// 8-armed octopus, a quadruped with thin legs, a mushroom spine (head on a thin neck).
//
// Each shape is a solid: a union of round cones (a segment whose radius varies linearly from one end to the other,
// closed by spheres). It is meshed the way segmentation meshes are made, with core/volume's own code:
//   voxelise (grid points inside the solid) -> largest 14-connected piece, cavities filled -> marching tetrahedra
//   (a closed 2-manifold by construction) -> Taubin smoothing -> quadric decimation (OpenMesh, link condition:
//   the genus cannot change).
// Two recipes:
//   * fine: isotropic voxels (2.5 per thinnest radius), decimation with a 45° normal bound: well-shaped triangles;
//   * needle-heavy: voxels 1:1:4 (z coarse, as a confocal stack), little smoothing, then an aggressive decimation
//     to a few hundred vertices with no quality bound, aiming at the decimated real spine meshes (200–900 vertices,
//     2–3 % of the triangles with an angle under 5°, the longest edge 10–20× the median). Reached: the vertex count
//     and a needle share of 1.3–2.8 % (quadrupeds 5–7 %); the edge ratio reaches 9–10 on dumbbells, 3–5 on coils
//     and the octopus.
// Every mesh is checked closed, manifold, one component, genus 0, outward before it is returned (else it throws).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh/mesh.hpp"

namespace wish::testing {

// Segment a -> b whose radius goes linearly from ra to rb; a sphere when a == b.
struct RoundCone {
  Eigen::Vector3d a, b;
  double ra = 0, rb = 0;
};

struct Solid {
  std::vector<RoundCone> parts;
  double thinnest_radius = 0;  // sets the voxel size
};

Solid coil_solid(int turns, double wire_ratio);   // coil radius 1, wire radius wire_ratio, axis z
Solid dumbbell_solid(double neck_ratio);          // bulbs of radius 1, neck radius neck_ratio
Solid octopus_solid(double arm_tip_ratio = 0.05);  // mantle radius 1, 8 curled tapering arms
Solid quadruped_solid(double leg_ratio = 0.06);    // body half-height 0.45; leg radius leg_ratio
Solid mushroom_spine_solid(double neck_ratio);    // head radius 0.5, neck radius 0.5 * neck_ratio, base knob

// A dendritic spine with its shape and pose as parameters (the needle-spine variants below): head radius, neck
// radius as a fraction of it, neck length, a head flattened along the neck (a capsule of length head_length across
// it otherwise), and the tilt of the neck from the z axis (the coarse axis of the needle recipe's voxels: a spine
// lying across the z slices gets other staircase needles than one along them).
struct SpineParams {
  double neck_ratio = 0.25;     // neck radius / head radius
  double head_radius = 0.5;
  double neck_length = 1.0;
  double head_length = 0.2;     // length of the head's capsule axis, across the neck
  double tilt_degrees = 0;      // rotation of the whole spine about the x axis
};
Solid spine_solid(const SpineParams& p);

enum class Tessellation { Fine, NeedleHeavy };

struct MeshingRecipe {
  double voxels_per_thinnest_radius = 2;
  double z_anisotropy = 1;             // z spacing / x spacing
  int smoothing_iterations = 10;
  long target_vertices = 6000;         // decimation with a 45-degree normal bound
  // Needle-heavy: after that bounded decimation, Taubin smoothing of s in `needle_smoothing` iterations
  // (fewer keep more of the 1:1:4 staircase's flat terraces) and a decimation WITHOUT a quality bound to each of
  // `needle_vertices`; the first mesh whose needle statistics fall in the band of the decimated real spines
  // (2-3 % of the triangles with an angle under 5 degrees, longest edge 10-20x the median) is returned, else the
  // closest one (the test reports it).
  std::vector<int> needle_smoothing;
  std::vector<long> needle_vertices;
  // Needle-heavy: further z anisotropies searched, in order, when no mesh at z_anisotropy fell in the band (a
  // coarser z gives longer staircase terraces, so longer edges; needle_spine_variants use it, the other shapes do
  // not: the search costs a voxelisation per anisotropy).
  std::vector<double> needle_more_z_anisotropies;
};

MeshingRecipe recipe_for(Tessellation t);
// The needle-heavy recipe with the z anisotropy search 4, 6, 8 (for the spine variants: small solids, cheap to voxelise).
MeshingRecipe needle_spine_recipe();

// Throws std::runtime_error when the result is not a closed, manifold, one-component, genus-0, outward mesh.
Mesh mesh_solid(const Solid& solid, const MeshingRecipe& recipe);

// The needle statistics of the decimated real spines.
struct NeedleStats {
  double small_angle_share = 0;  // of the triangles, those with an angle under 5 degrees
  double longest_over_median_edge = 0;
};
NeedleStats needle_stats(const Mesh& mesh);

// One generated shape of the sweep.
struct HardShape {
  std::string family;  // "coil", "dumbbell", "octopus", "quadruped", "mushroom_spine"
  std::string name;    // with its parameters, e.g. "coil 12 turns, wire 1/20"
  Tessellation tessellation = Tessellation::Fine;
  Solid solid;
};

// The parameter sizes of each family (coils 3/6/12 turns with wire 1/10, 1/15, 1/20; dumbbells 1:5, 1:10, 1:20; the
// octopus; quadrupeds with legs 0.08 and 0.05; mushroom spines with necks 1:4 and 1:8), each in both tessellations.
std::vector<HardShape> hard_shape_catalogue();

// Decimated needle-heavy dendritic spines for the flow figures of issue 24 item 3 (>= 90 % of them should end the map
// chain on a flow): 12 shapes and poses (necks 1:3 to 1:8, heads 0.35-0.6, short and long necks, tilts 0-90
// degrees), family "spine_variant", tessellation NeedleHeavy, meshed with needle_spine_recipe().
std::vector<HardShape> needle_spine_variants();

}  // namespace wish::testing
