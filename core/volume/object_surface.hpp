#pragma once
// The surface of one object of a label image, ready for the spherical map: a closed, vertex-manifold, outward
// triangle mesh of genus 0 in physical units (anisotropic spacing honoured).
// Steps (each timed, each change reported as a repair):
//   1. extraction: the object's voxels in its bounding box padded by two voxels, so the
//      surface closes inside the box (a truncated object is closed along the volume border);
//      keep the largest 14-connected piece (a label may be split), fill enclosed cavities;
//   2. surface: marching tetrahedra on the Kuhn triangulation, a closed 2-manifold by construction
//      (marching_tetrahedra.hpp); genus from the Euler characteristic, χ = 2 − 2g;
//      when g > 0, the handles are removed by cutting or filling, whichever changes less volume
//      (topology_repair.hpp); the repair is kept (listed with its volume change) when it changes at most
//      `max_repair_share` of the object's voxels, else the object is refused with code "genus_nonzero" and a message
//      that says what was found (genus, pieces, voxels touching other labels) and what the repair would change;
//   3. smoothing: Taubin λ|μ (taubin_smoothing.hpp), then a uniform scale about the centroid that restores the
//      enclosed volume of step 2 exactly (Taubin alone shrinks slightly);
//   4. decimation: quadric edge collapse to `target_vertices` (decimation.hpp), topology re-checked.
// Tolerances (tests/volume, voxelised spheres and ellipsoids with semi-axes of 8 to 16 voxels, isotropic and
// anisotropic spacing): the enclosed volume is within 2 % of voxel_count × voxel volume and of the analytic shape's
// (measured 0.2-0.4 % and 1.0-1.4 %); the area is 0 to 12 % above the analytic shape's (measured +6.9 to +10.0 %:
// light smoothing leaves part of the staircase, which only adds area; before smoothing +24 to +27 %).

#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/volume/label_image.hpp"
#include "core/volume/label_objects.hpp"
#include "core/volume/topology_repair.hpp"

namespace wish::volume {

struct SurfaceOptions {
  int smoothing_iterations = 10;
  double taubin_lambda = 0.5, taubin_mu = -0.53;
  std::int64_t target_vertices = 10'000;  // the paper's resolution; 0 or fewer keeps every vertex
  // A handle repair is kept when it changes at most this share of the object's voxels (removed + added): 0 never
  // repairs (--no-close-handles), infinity always does (--close-handles). The default is from the generated hard
  // cases and the UroCell handles (docs/accuracy.md, "Handles").
  double max_repair_share = kDefaultMaxRepairShare;
  static constexpr double kDefaultMaxRepairShare = 0.10;
  std::int64_t max_box_voxels = 64ll << 20;  // padded bounding box of one object
};

struct SurfaceTimings {
  double extraction = 0, surface = 0, smoothing = 0, decimation = 0;  // seconds
};

struct ObjectSurface {
  Mesh mesh;                        // empty when refused before a surface existed
  bool ok = false;                  // closed manifold genus 0, ready to map
  std::string refusal_code;         // "genus_nonzero", "not_manifold", "box_too_large", ... when !ok
  std::string refusal;              // a sentence with the numbers
  int genus = -1;                   // of the voxel object's surface before any repair (-1: not a closed surface)
  std::vector<std::string> repairs;
  int pieces = 1;                   // 14-connected pieces of the object's voxels (the largest is meshed)
  std::int64_t touching_voxels = 0; // the object's voxels with a 6-neighbour of another object
  std::vector<std::uint32_t> touching_ids;  // those other objects' ids, ascending
  TopologyRepairFigures repair;     // genus > 0: what removing the handles changes (measured whether kept or not)
  bool repaired = false;            // that repair was kept
  std::int64_t voxels_meshed = 0;   // after piece selection, cavity filling and handle repair
  double voxel_volume = 0;          // voxels_meshed × voxel volume
  double raw_area = 0, raw_volume = 0;  // marching tetrahedra surface, before smoothing
  double area = 0, volume = 0;          // final mesh
  std::int64_t vertices_before_decimation = 0;
  SurfaceTimings timings;
};

ObjectSurface object_surface(const LabelImage& image, const ObjectSet& objects, const VolumeObject& object,
                             const SurfaceOptions& options = {});

double mesh_area(const Mesh& mesh);
double mesh_volume(const Mesh& mesh);  // signed, positive for an outward closed surface

}  // namespace wish::volume
