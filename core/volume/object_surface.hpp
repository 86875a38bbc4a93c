#pragma once
// The surface of one object of a label image, ready for the spherical map: a closed, vertex-manifold, outward
// triangle mesh of genus 0 in physical units (anisotropic spacing honoured).
// Steps (each timed, each change reported as a repair):
//   1. extraction: the object's voxels in its bounding box padded by one voxel (plus the closing radius), so the
//      surface closes inside the box (a truncated object is closed along the volume border);
//      keep the largest 14-connected piece (a label may be split), fill enclosed cavities;
//   2. surface: marching tetrahedra on the Kuhn triangulation, a closed 2-manifold by construction
//      (marching_tetrahedra.hpp); genus from the Euler characteristic, χ = 2 − 2g;
//      when g > 0, morphological closing of radius 1, 2, ... up to `max_closing_radius` until g = 0 is tried; it is
//      kept (listed as a repair with the volume it added) when `close_handles` is set, or by default when it adds
//      at most `default_closing_share` of the object's volume; else the object is refused with code
//      "genus_nonzero" and a message that says what was found (genus, pieces, voxels touching other labels) and
//      what --close-handles would do (the radius and the volume change, or that it does not close the handles);
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

namespace wish::volume {

struct SurfaceOptions {
  int smoothing_iterations = 10;
  double taubin_lambda = 0.5, taubin_mu = -0.53;
  std::int64_t target_vertices = 10'000;  // the paper's resolution; 0 or fewer keeps every vertex
  bool close_handles = false;              // keep a closing that removes the handles, whatever volume it adds
  int max_closing_radius = 3;
  // Without close_handles, a closing is kept when it adds at most this share of the voxels (0: never). The default
  // is from the UroCell and touching-sphere measurements (docs/accuracy.md, "Handles").
  double default_closing_share = 0.01;
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
  int genus = -1;                   // of the voxel object's surface before any closing (-1: not a closed surface)
  std::vector<std::string> repairs;
  int pieces = 1;                   // 14-connected pieces of the object's voxels (the largest is meshed)
  std::int64_t touching_voxels = 0; // the object's voxels with a 6-neighbour of another object
  std::vector<std::uint32_t> touching_ids;  // those other objects' ids, ascending
  int closing_radius = 0;           // genus > 0: the closing radius that removes the handles (0: none up to the limit)
  double closing_share = 0;         // and the share of voxels it adds (kept or not)
  std::int64_t voxels_meshed = 0;   // after piece selection, cavity filling and closing
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
