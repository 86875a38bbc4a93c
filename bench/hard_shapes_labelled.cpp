// A LABELLED set of generated hard shapes for the accuracy table (issue 25 item 1): the five families of
// tests/synth/hard_shapes.hpp (coil, dumbbell, octopus, quadruped, mushroom_spine) as classes, N shapes each, every
// one with its own parameters (turns and wire, neck, arm tips, legs), a mild anisotropic stretch, a random size and
// a random rotation, written as class folders of binary PLY that `wish train` and bench/descriptor_accuracy_bench read:
//   hard_shapes_labelled OUTDIR [--per-class N (15)] [--seed S (1)] [--vertices V (3000)] [--families a,b (all)]
// --families makes only those classes and --from I only shapes I.. of each (the same shapes as in a full run), so
// several processes can share the work.
// Deterministic by seed: the parameters come from std::mt19937_64's raw output (its sequence is fixed by the standard;
// the std:: distributions are not), seeded per (seed, class, index), so one shape does not depend on the others.
// The pose is applied to the solid BEFORE it is voxelised, so two shapes of a family differ in their voxel staircase
// as two segmentations of one object would, not only by a rigid motion of the same mesh (to which ξ is invariant by
// construction). Each solid is first scaled to a bounding-box half-diagonal of 1, so size alone (then drawn the same
// way for every class) does not tell the classes apart. OUTDIR/<class>/shapes.csv lists every shape's parameters.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "core/io/mesh_io.hpp"
#include "tests/synth/hard_shapes.hpp"

namespace fs = std::filesystem;
using wish::testing::Solid;

namespace {

// Uniform in [lo, hi) from the generator's raw 64-bit output (portable, unlike std::uniform_real_distribution).
double uniform(std::mt19937_64& g, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(g() >> 11) * 0x1.0p-53;
}

// A uniformly random rotation (Shoemake's method: a uniform unit quaternion from three uniforms).
Eigen::Matrix3d random_rotation(std::mt19937_64& g) {
  const double u1 = uniform(g, 0, 1), u2 = uniform(g, 0, 2 * std::numbers::pi), u3 = uniform(g, 0, 2 * std::numbers::pi);
  const Eigen::Quaterniond q(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2), std::sqrt(1 - u1) * std::cos(u2),
                             std::sqrt(u1) * std::sin(u3));
  return q.normalized().toRotationMatrix();
}

struct Drawn {
  Solid solid;
  std::string parameters;  // for shapes.csv
};

// The family's own parameters. Ranges keep every part at least ~1/14 of the shape (the finest parts of the hard-shape
// sweep, 1/20, take 30-80 s each to voxelise and decimate; these take seconds) and stay genus 0 at the fine recipe.
Drawn draw_family(const std::string& family, std::mt19937_64& g) {
  char buf[128];
  if (family == "coil") {
    const int turns = 3 + static_cast<int>(uniform(g, 0, 6));  // 3..8
    const double wire = uniform(g, 1.0 / 14, 1.0 / 8);
    std::snprintf(buf, sizeof buf, "turns=%d wire=%.4f", turns, wire);
    return {wish::testing::coil_solid(turns, wire), buf};
  }
  if (family == "dumbbell") {
    const double neck = uniform(g, 0.08, 0.3);
    std::snprintf(buf, sizeof buf, "neck=%.4f", neck);
    return {wish::testing::dumbbell_solid(neck), buf};
  }
  if (family == "octopus") {
    const double tips = uniform(g, 0.06, 0.12);
    std::snprintf(buf, sizeof buf, "arm_tips=%.4f", tips);
    return {wish::testing::octopus_solid(tips), buf};
  }
  if (family == "quadruped") {
    const double legs = uniform(g, 0.08, 0.13);
    std::snprintf(buf, sizeof buf, "legs=%.4f", legs);
    return {wish::testing::quadruped_solid(legs), buf};
  }
  const double neck = uniform(g, 0.12, 0.4);
  std::snprintf(buf, sizeof buf, "neck=%.4f", neck);
  return {wish::testing::mushroom_spine_solid(neck), buf};
}

// x -> s R D (x - centre) / half_diagonal. A round cone under an anisotropic stretch is no longer a round cone: its
// radii are scaled by the stretch's geometric mean (the stretch is mild, 0.85-1.15 per axis).
Solid posed(const Solid& in, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& stretch, double size) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& c : in.parts) {
    const double r = std::max(c.ra, c.rb);
    lo = lo.cwiseMin(c.a.cwiseMin(c.b) - Eigen::Vector3d::Constant(r));
    hi = hi.cwiseMax(c.a.cwiseMax(c.b) + Eigen::Vector3d::Constant(r));
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double unit = 2 / (hi - lo).norm();
  const double radius_factor = size * unit * std::cbrt(stretch.prod());
  const Eigen::Matrix3d A = size * unit * rotation * stretch.asDiagonal();
  Solid out;
  for (const auto& c : in.parts) out.parts.push_back({A * (c.a - centre), A * (c.b - centre), c.ra * radius_factor, c.rb * radius_factor});
  out.thinnest_radius = in.thinnest_radius * radius_factor;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]).starts_with("-")) {
    std::fprintf(stderr, "usage: %s OUTDIR [--per-class N] [--seed S] [--vertices V] [--families a,b] [--from I]\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1];
  int per_class = 15;
  std::uint64_t seed = 1;
  long vertices = 3000;
  std::string only;  // comma-separated families; empty: all
  int from = 0;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s needs a value\n", a.c_str());
      return 2;
    }
    const std::string v = argv[++i];
    if (a == "--per-class") per_class = std::stoi(v);
    else if (a == "--seed") seed = std::stoull(v);
    else if (a == "--vertices") vertices = std::stol(v);
    else if (a == "--families") only = "," + v + ",";
    else if (a == "--from") from = std::stoi(v);
    else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (per_class < 1 || vertices < 100) {
    std::fprintf(stderr, "--per-class must be >= 1 and --vertices >= 100\n");
    return 2;
  }
  wish::testing::MeshingRecipe recipe = wish::testing::recipe_for(wish::testing::Tessellation::Fine);
  recipe.target_vertices = vertices;
  const std::vector<std::string> families{"coil", "dumbbell", "mushroom_spine", "octopus", "quadruped"};
  for (std::size_t f = 0; f < families.size(); ++f) {
    // f stays the family's index in the full list: the seeds, so the shapes, do not depend on --families.
    if (!only.empty() && only.find("," + families[f] + ",") == std::string::npos) continue;
    fs::create_directories(out / families[f]);
    const fs::path list = out / families[f] / (from > 0 ? "shapes-from-" + std::to_string(from) + ".csv" : "shapes.csv");
    std::ofstream csv(list);
    csv << "class,file,parameters,size,stretch_x,stretch_y,stretch_z,vertices,attempts,seconds\n";
    for (int i = from; i < per_class; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      // A draw whose mesh is not a closed genus-0 surface (a voxel bridge) is replaced by the next attempt's draw;
      // attempts are part of the seed, so the set stays deterministic.
      for (int attempt = 0;; ++attempt) {
        std::mt19937_64 g(seed * 1000003 + f * 10007 + static_cast<std::uint64_t>(i) * 101 + static_cast<std::uint64_t>(attempt));
        const Drawn d = draw_family(families[f], g);
        const Eigen::Vector3d stretch(uniform(g, 0.85, 1.15), uniform(g, 0.85, 1.15), uniform(g, 0.85, 1.15));
        const double size = std::exp(uniform(g, std::log(0.5), std::log(2.0)));
        const Eigen::Matrix3d rotation = random_rotation(g);
        try {
          const wish::Mesh mesh = wish::testing::mesh_solid(posed(d.solid, rotation, stretch, size), recipe);
          char name[64];
          std::snprintf(name, sizeof name, "%s_%03d.ply", families[f].c_str(), i);
          wish::write_mesh_file(mesh, out / families[f] / name);
          const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          csv << families[f] << "," << name << "," << d.parameters << "," << size << "," << stretch.x() << "," << stretch.y()
              << "," << stretch.z() << "," << mesh.vertex_count() << "," << attempt + 1 << "," << s << "\n";
          csv.flush();
          std::printf("%s/%s %s size %.2f V %ld (%d attempt(s), %.1f s)\n", families[f].c_str(), name, d.parameters.c_str(),
                      size, static_cast<long>(mesh.vertex_count()), attempt + 1, s);
          std::fflush(stdout);
          break;
        } catch (const std::exception& e) {
          if (attempt >= 9) {
            std::fprintf(stderr, "%s %d: no closed genus-0 mesh in 10 draws (%s)\n", families[f].c_str(), i, e.what());
            return 1;
          }
        }
      }
    }
  }
  return 0;
}
