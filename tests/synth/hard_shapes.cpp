// Hard genus-0 solids as unions of round cones, voxelised and meshed with core/volume (see hard_shapes.hpp).
#include "tests/synth/hard_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "core/volume/binary_volume.hpp"
#include "core/volume/decimation.hpp"
#include "core/volume/marching_tetrahedra.hpp"
#include "core/volume/surface_topology.hpp"
#include "core/volume/taubin_smoothing.hpp"

namespace wish::testing {
namespace {

constexpr double kPi = std::numbers::pi;

// A tube of radius r0 -> r1 along a polyline (consecutive round cones share their end spheres, so the union is a
// smooth-jointed tube).
void add_tube(Solid& s, const std::vector<Eigen::Vector3d>& path, double r0, double r1) {
  const auto n = path.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double t0 = static_cast<double>(i) / static_cast<double>(n - 1), t1 = static_cast<double>(i + 1) / static_cast<double>(n - 1);
    s.parts.push_back({path[i], path[i + 1], r0 + (r1 - r0) * t0, r0 + (r1 - r0) * t1});
  }
}

void add_ball(Solid& s, const Eigen::Vector3d& c, double r) { s.parts.push_back({c, c, r, r}); }

// Inside test of a round cone: distance to the segment against the radius interpolated at the closest point.
bool inside(const RoundCone& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = c.b - c.a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - c.a).dot(d) / len2, 0.0, 1.0) : 0.0;
  const double r = c.ra + (c.rb - c.ra) * t;
  return (p - (c.a + t * d)).squaredNorm() <= r * r;
}

}  // namespace

Solid coil_solid(int turns, double wire_ratio) {
  // Coil radius 1 about the z axis; the pitch keeps 6 wire radii of air between turns, so the coarse z voxels of the
  // needle recipe (4/3 of a wire radius) never bridge two turns (a bridge would be a handle: genus > 0).
  Solid s;
  const double r = wire_ratio, pitch = 8 * r;
  const int segments = std::max(64, static_cast<int>(std::ceil(turns * 2 * kPi / (0.5 * r))));
  std::vector<Eigen::Vector3d> path;
  for (int i = 0; i <= segments; ++i) {
    const double t = turns * 2 * kPi * i / segments;
    path.emplace_back(std::cos(t), std::sin(t), pitch * t / (2 * kPi));
  }
  add_tube(s, path, r, r);
  s.thinnest_radius = r;
  return s;
}

Solid dumbbell_solid(double neck_ratio) {
  Solid s;
  add_ball(s, {-2, 0, 0}, 1);
  add_ball(s, {2, 0, 0}, 1);
  add_tube(s, {{-1.5, 0, 0}, {1.5, 0, 0}}, neck_ratio, neck_ratio);
  s.thinnest_radius = neck_ratio;
  return s;
}

Solid octopus_solid(double arm_tip_ratio) {
  // Mantle (a ball on a smaller head ball) and 8 arms leaving the head's equator, curling down and outwards; the
  // arms taper from 0.22 to arm_tip_ratio and stay apart (their tips curl sideways by less than half the gap).
  Solid s;
  add_ball(s, {0, 0, 0.9}, 1.0);
  add_ball(s, {0, 0, 0}, 0.7);
  for (int k = 0; k < 8; ++k) {
    const double phi = 2 * kPi * k / 8;
    const Eigen::Vector3d radial(std::cos(phi), std::sin(phi), 0), side(-std::sin(phi), std::cos(phi), 0);
    std::vector<Eigen::Vector3d> path;
    const int n = 24;
    for (int i = 0; i <= n; ++i) {
      const double u = static_cast<double>(i) / n;  // 0 at the head, 1 at the tip
      const double out = 0.5 + 2.2 * u, down = -0.2 - 1.2 * std::sin(0.5 * kPi * u) + 0.6 * u * u, curl = 0.35 * std::sin(2.5 * kPi * u) * u;
      path.push_back(out * radial + curl * side + Eigen::Vector3d(0, 0, down));
    }
    add_tube(s, path, 0.22, arm_tip_ratio);
  }
  s.thinnest_radius = arm_tip_ratio;
  return s;
}

Solid quadruped_solid(double leg_ratio) {
  // Body along x, head on a neck, four straight thin legs with a knee bend, a thin tail.
  Solid s;
  add_tube(s, {{-1.0, 0, 0}, {1.0, 0, 0}}, 0.45, 0.42);
  add_tube(s, {{1.2, 0, 0.2}, {1.7, 0, 0.8}}, 0.2, 0.16);
  add_ball(s, {1.9, 0, 0.9}, 0.3);
  add_tube(s, {{2.05, 0, 0.85}, {2.4, 0, 0.75}}, 0.14, 0.08);  // snout
  for (const double x : {-0.8, 0.8})
    for (const double y : {-0.25, 0.25}) {
      const Eigen::Vector3d hip(x, y, -0.2), knee(x + 0.1, y * 1.2, -0.9), foot(x, y * 1.2, -1.6);
      add_tube(s, {hip, knee, foot}, leg_ratio * 1.4, leg_ratio);
    }
  add_tube(s, {{-1.3, 0, 0.1}, {-1.9, 0, 0.5}, {-2.4, 0, 0.6}}, 0.08, std::max(0.03, leg_ratio * 0.6));
  s.thinnest_radius = std::min(leg_ratio, std::max(0.03, leg_ratio * 0.6));
  return s;
}

Solid mushroom_spine_solid(double neck_ratio) {
  // A dendritic spine: a base knob where it leaves the dendrite, a thin neck, a flattened head.
  Solid s;
  const double head = 0.5, neck = head * neck_ratio;
  add_tube(s, {{0, 0, 0}, {0, 0, 0.15}}, 0.3, 0.2);
  add_tube(s, {{0, 0, 0.15}, {0.05, 0, 0.6}, {0, 0.03, 1.1}}, std::max(neck * 1.5, 0.06), neck);
  add_tube(s, {{-0.1, 0, 1.45}, {0.1, 0, 1.45}}, head, head * 0.9);
  s.thinnest_radius = neck;
  return s;
}

Solid spine_solid(const SpineParams& p) {
  // Base knob on the dendrite at the origin, a slightly bent neck up the z axis, the head's capsule across its top;
  // then the whole spine tilted about the x axis.
  Solid s;
  const double neck = p.head_radius * p.neck_ratio, top = 0.15 + p.neck_length;
  add_tube(s, {{0, 0, 0}, {0, 0, 0.15}}, 0.3, 0.2);
  add_tube(s, {{0, 0, 0.15}, {0.05, 0, 0.15 + 0.45 * p.neck_length}, {0, 0.03, top}}, std::max(neck * 1.5, 0.06), neck);
  const double centre = top + 0.7 * p.head_radius;  // the neck enters the head's lower part
  add_tube(s, {{-0.5 * p.head_length, 0, centre}, {0.5 * p.head_length, 0, centre}}, p.head_radius, 0.9 * p.head_radius);
  const double t = p.tilt_degrees * kPi / 180;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(t, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (RoundCone& c : s.parts) {
    c.a = rotation * c.a;
    c.b = rotation * c.b;
  }
  s.thinnest_radius = neck;
  return s;
}

MeshingRecipe recipe_for(Tessellation t) {
  MeshingRecipe r;
  if (t == Tessellation::Fine) return r;
  r.z_anisotropy = 4;
  r.target_vertices = 3000;
  r.needle_smoothing = {0, 1, 2, 4};
  r.needle_vertices = {250, 350, 450, 600, 750, 900};
  return r;
}

MeshingRecipe needle_spine_recipe() {
  MeshingRecipe r = recipe_for(Tessellation::NeedleHeavy);
  r.needle_more_z_anisotropies = {6, 8};
  return r;
}

namespace {

Mesh voxel_surface(const Solid& solid, const MeshingRecipe& recipe) {
  const double h = solid.thinnest_radius / recipe.voxels_per_thinnest_radius;
  const Eigen::Vector3d spacing(h, h, h * recipe.z_anisotropy);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& c : solid.parts) {
    const double r = std::max(c.ra, c.rb);
    lo = lo.cwiseMin(c.a.cwiseMin(c.b) - Eigen::Vector3d::Constant(r));
    hi = hi.cwiseMax(c.a.cwiseMax(c.b) + Eigen::Vector3d::Constant(r));
  }
  volume::BinaryVolume v;
  v.spacing = spacing;
  v.origin = lo - 2 * spacing;  // two empty layers: the border stays background
  for (int k = 0; k < 3; ++k) v.dims[static_cast<std::size_t>(k)] = static_cast<int>(std::ceil((hi[k] - lo[k]) / spacing[k])) + 5;
  v.labels.assign(static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2], 0);
  // Rasterise each part in its own bounding box (a union: a voxel inside any part is inside).
  for (const auto& c : solid.parts) {
    const double r = std::max(c.ra, c.rb);
    const Eigen::Vector3d plo = c.a.cwiseMin(c.b) - Eigen::Vector3d::Constant(r), phi = c.a.cwiseMax(c.b) + Eigen::Vector3d::Constant(r);
    int i0[3], i1[3];
    for (int k = 0; k < 3; ++k) {
      i0[k] = std::max(1, static_cast<int>(std::floor((plo[k] - v.origin[k]) / spacing[k])));
      i1[k] = std::min(v.dims[static_cast<std::size_t>(k)] - 2, static_cast<int>(std::ceil((phi[k] - v.origin[k]) / spacing[k])));
    }
    for (int z = i0[2]; z <= i1[2]; ++z)
      for (int y = i0[1]; y <= i1[1]; ++y)
        for (int x = i0[0]; x <= i1[0]; ++x) {
          auto& label = v.labels[v.index(x, y, z)];
          if (!label && inside(c, v.origin + spacing.cwiseProduct(Eigen::Vector3d(x, y, z)))) label = 1;
        }
  }
  volume::keep_largest_component(v);
  volume::fill_cavities(v);
  return volume::marching_tetrahedra(v);
}

bool in_spine_band(const NeedleStats& s) {
  return s.small_angle_share >= 0.02 && s.small_angle_share <= 0.03 && s.longest_over_median_edge >= 10 &&
         s.longest_over_median_edge <= 20;
}

// Distance to the band, in band widths (0 inside).
double band_distance(const NeedleStats& s) {
  const auto outside = [](double x, double lo, double hi) { return x < lo ? (lo - x) / (hi - lo) : x > hi ? (x - hi) / (hi - lo) : 0.0; };
  return outside(s.small_angle_share, 0.02, 0.03) + outside(s.longest_over_median_edge, 10, 20);
}

}  // namespace

Mesh mesh_solid(const Solid& solid, const MeshingRecipe& recipe) {
  if (!recipe.needle_vertices.empty() && !recipe.needle_more_z_anisotropies.empty()) {
    // The anisotropy search: the first mesh in the band, else the closest over every anisotropy.
    MeshingRecipe one = recipe;
    one.needle_more_z_anisotropies.clear();
    std::vector<double> anisotropies{recipe.z_anisotropy};
    anisotropies.insert(anisotropies.end(), recipe.needle_more_z_anisotropies.begin(), recipe.needle_more_z_anisotropies.end());
    Mesh best;
    double best_distance = 1e300;
    for (const double z : anisotropies) {
      one.z_anisotropy = z;
      Mesh mesh;
      try {
        mesh = mesh_solid(solid, one);
      } catch (const std::runtime_error&) {
        continue;  // no closed genus-0 decimation at this anisotropy
      }
      const double d = band_distance(needle_stats(mesh));
      if (d == 0) return mesh;
      if (d < best_distance) {
        best_distance = d;
        best = std::move(mesh);
      }
    }
    if (best.vertex_count() == 0) throw std::runtime_error("hard shape: no needle-heavy decimation stayed a closed genus-0 mesh");
    return best;
  }
  const Mesh surface = voxel_surface(solid, recipe);
  const auto check = [](const Mesh& m) {
    const volume::SurfaceTopology t = volume::analyze_surface(m);
    return t.closed_genus0();
  };
  if (recipe.needle_vertices.empty()) {
    Mesh mesh = surface;
    if (recipe.smoothing_iterations > 0) volume::taubin_smooth(mesh, recipe.smoothing_iterations);
    volume::decimate_to_vertices(mesh, recipe.target_vertices);
    if (!check(mesh)) throw std::runtime_error("hard shape is not a closed genus-0 mesh: " + volume::analyze_surface(mesh).describe());
    return mesh;
  }
  Mesh best;
  double best_distance = 1e300;
  for (const int smoothing : recipe.needle_smoothing) {
    Mesh base = surface;
    if (smoothing > 0) volume::taubin_smooth(base, smoothing);
    volume::decimate_to_vertices(base, recipe.target_vertices);
    for (const long n : recipe.needle_vertices) {
      Mesh mesh = base;
      volume::decimate_to_vertices(mesh, n, /*max_normal_deviation_degrees=*/180);
      // An unbounded collapse can leave an exactly flat (zero-area) triangle: not a clean test mesh, skipped.
      if (!check(mesh)) continue;
      const NeedleStats s = needle_stats(mesh);
      if (in_spine_band(s)) return mesh;
      if (const double d = band_distance(s); d < best_distance) {
        best_distance = d;
        best = std::move(mesh);
      }
    }
  }
  if (best.vertex_count() == 0) throw std::runtime_error("hard shape: no needle-heavy decimation stayed a closed genus-0 mesh");
  return best;
}

NeedleStats needle_stats(const Mesh& mesh) {
  NeedleStats s;
  std::vector<double> edges;
  edges.reserve(static_cast<std::size_t>(3 * mesh.face_count()));
  const double limit = std::cos(5.0 * kPi / 180);
  std::int64_t small = 0;
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    bool needle = false;
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d p = mesh.vertices.row(mesh.faces(f, k)), q = mesh.vertices.row(mesh.faces(f, (k + 1) % 3)),
                               r = mesh.vertices.row(mesh.faces(f, (k + 2) % 3));
      const Eigen::RowVector3d u = q - p, w = r - p;
      const double nu = u.norm(), nw = w.norm();
      if (nu == 0 || nw == 0 || u.dot(w) / (nu * nw) > limit) needle = true;  // the angle at p is under 5 degrees
      if (mesh.faces(f, k) < mesh.faces(f, (k + 1) % 3)) edges.push_back(nu);  // each edge once (closed, oriented)
    }
    small += needle;
  }
  s.small_angle_share = mesh.face_count() > 0 ? static_cast<double>(small) / static_cast<double>(mesh.face_count()) : 0;
  if (!edges.empty()) {
    std::nth_element(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(edges.size() / 2), edges.end());
    const double median = edges[edges.size() / 2];
    s.longest_over_median_edge = *std::max_element(edges.begin(), edges.end()) / median;
  }
  return s;
}

std::vector<HardShape> hard_shape_catalogue() {
  std::vector<HardShape> out;
  const auto add = [&](const std::string& family, const std::string& name, const Solid& solid) {
    out.push_back({family, name, Tessellation::Fine, solid});
    out.push_back({family, name, Tessellation::NeedleHeavy, solid});
  };
  add("coil", "coil 3 turns, wire 1/10", coil_solid(3, 0.1));
  add("coil", "coil 6 turns, wire 1/15", coil_solid(6, 1.0 / 15));
  add("coil", "coil 12 turns, wire 1/20", coil_solid(12, 0.05));
  add("dumbbell", "dumbbell neck 1:5", dumbbell_solid(0.2));
  add("dumbbell", "dumbbell neck 1:10", dumbbell_solid(0.1));
  add("dumbbell", "dumbbell neck 1:20", dumbbell_solid(0.05));
  add("octopus", "octopus 8 arms, tips 1/20", octopus_solid(0.05));
  add("quadruped", "quadruped legs 0.08", quadruped_solid(0.08));
  add("quadruped", "quadruped legs 0.05", quadruped_solid(0.05));
  add("mushroom_spine", "mushroom spine neck 1:4", mushroom_spine_solid(0.25));
  add("mushroom_spine", "mushroom spine neck 1:8", mushroom_spine_solid(0.125));
  return out;
}

std::vector<HardShape> needle_spine_variants() {
  struct Variant {
    const char* name;
    SpineParams p;
  };
  // neck ratio, head radius, neck length, head length, tilt
  const Variant variants[] = {
      {"spine neck 1:3, head 0.5, upright", {1.0 / 3, 0.5, 1.0, 0.2, 0}},
      {"spine neck 1:4, head 0.5, tilt 45", {0.25, 0.5, 1.0, 0.2, 45}},
      {"spine neck 1:4, head 0.6, lying", {0.25, 0.6, 0.8, 0.3, 90}},
      {"spine neck 1:5, head 0.4, long neck", {0.2, 0.4, 1.6, 0.1, 0}},
      {"spine neck 1:5, head 0.5, tilt 30", {0.2, 0.5, 1.0, 0.4, 30}},
      {"spine neck 1:6, head 0.5, upright", {1.0 / 6, 0.5, 1.0, 0.2, 0}},
      {"spine neck 1:6, head 0.35, tilt 60", {1.0 / 6, 0.35, 0.9, 0.1, 60}},
      {"spine neck 1:6, head 0.6, lying", {1.0 / 6, 0.6, 1.2, 0.2, 90}},
      {"spine neck 1:8, head 0.5, tilt 20", {0.125, 0.5, 1.0, 0.2, 20}},
      {"spine neck 1:8, head 0.6, short neck", {0.125, 0.6, 0.6, 0.3, 0}},
      {"spine neck 1:3, head 0.4, lying, long neck", {1.0 / 3, 0.4, 1.5, 0.2, 90}},
      {"spine neck 1:4, head 0.45, flat head", {0.25, 0.45, 1.1, 0.6, 10}},
  };
  std::vector<HardShape> out;
  for (const Variant& v : variants) out.push_back({"spine_variant", v.name, Tessellation::NeedleHeavy, spine_solid(v.p)});
  return out;
}

}  // namespace wish::testing
