#pragma once
// Conformal map of a closed genus-0 mesh onto the unit sphere (paper §4; ../shared/design/spherical-map.md).
// Entry point: compute_spherical_map(). Methods: discrete Willmore flow in curvature space with spin
// transformations (Crane, Pinkall, Schröder 2013) and conformalized mean curvature flow (Kazhdan et al. 2012).
// Every map is projected to the sphere, Möbius-normalised (area-centre balancing with input vertex areas as
// weights) and verified; a map that fails verification is never reported as Ok.
//
// Preconditions: the mesh passed prepare_for_mapping() (closed, manifold, one component, genus 0, outward).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/common/deadline.hpp"
#include "core/mesh/mesh.hpp"

namespace wish {

enum class MapMethod { Willmore, Cmcf };
enum class LinearSolverKind { Cholmod, EigenSimplicial };

const char* to_string(MapMethod method);
MapMethod map_method_from_name(const std::string& name);  // "willmore" | "cmcf"; throws InvalidInputError

struct WillmoreOptions {
  double tau = 0.95;                 // dimensionless step: rho = -tau * P(H) (spherical-map.md §3)
  int max_steps = 20;                // step cap (the paper uses 10 on nuclei)
  double roundness_tolerance = 2e-3; // stop when std(r)/mean(r) falls below
  double energy_tolerance = 1e-4;    // ... or when the relative energy decrease per step falls below
  double min_tau = 0.05;             // step rejection halves tau down to this, then gives up
  bool filtered = false;             // low-pass filtered flow for noisy segmentation meshes
  double filter_strength = 2.0;      // sigma = filter_strength * (mean edge length)^2
  int max_inverse_iterations = 5;    // inverse power iteration for the smallest eigenvector
  // Added: an eigen-solve whose relative residual stays above this after max_inverse_iterations rejects the step.
  double max_eigen_residual = 1e-4;
  double energy_increase_tolerance = 1e-3;  // reject a step raising E_W by more than this fraction
  // Added: solve the Dirac eigenproblem in its complex Hermitian 2V×2V form (same λ, ~2× fewer Cholesky flops)
  // instead of the real symmetric 4V×4V form (spherical-map.md §4, §9).
  bool complex_dirac = true;
};

struct CmcfOptions {
  double delta = 1.0;                // time step at total area 4*pi
  int max_steps = 30;
  double roundness_tolerance = 5e-3;
};

struct MapVerificationThresholds {
  double degenerate_area = 1e-12;    // spherical triangle area below this * 4*pi counts as degenerate
  double max_conformal_p99 = 5.0;    // quasi-conformal ratio K (p99) above this fails verification
};

struct SphericalMapOptions {
  MapMethod method = MapMethod::Willmore;
  WillmoreOptions willmore;
  CmcfOptions cmcf;
  LinearSolverKind solver = LinearSolverKind::Cholmod;
  bool fallback = true;              // on failure: more steps, then the filtered flow, then cMCF
  MapVerificationThresholds verification;
};

// Figures of one sphere map, compared with the input mesh.
struct MapQuality {
  long flipped_faces = 0;            // must be 0 for a bijective map
  long degenerate_faces = 0;
  int degree = 0;                    // signed sphere area / 4*pi rounded; +1 for an orientation-preserving cover
  double min_face_area = 0;          // smallest spherical triangle area (unit sphere)
  double conformal_mean = 0, conformal_p99 = 0, conformal_max = 0;  // per-face K = sigma1/sigma2 >= 1
  double area_distortion = 0;        // exp(mean |log(area ratio)|), areas normalised to equal totals
  double roundness = 0;              // std(r)/mean(r) of the flowed surface before projection
  double mobius_centroid = 0;        // |sum w_i u_i| after Möbius balancing
  long non_finite_vertices = 0;      // NaN/Inf sphere positions (any > 0 fails verification)
  int mobius_iterations = 0;         // iterations of the area-centre balancing
};

// One flow step, accepted or rejected.
struct FlowStepRecord {
  int step = 0;
  double tau = 0;
  double energy = 0;                 // Willmore energy sum_i M_i H_i^2 after the step (4*pi for a round sphere)
  double roundness = 0;
  double eigen_residual = 0;         // relative residual of the smallest eigenvector
  bool accepted = true;
  double seconds = 0;
  // Added: detail of the step (Willmore flow; cMCF fills what applies).
  double rayleigh = 0;               // gamma / mean(diag E): how far rho was from integrable (0 = exactly)
  int inverse_iterations = 0;
  double eigen_shift = 0;            // epsilon actually added to the Dirac matrix
  double geometry_seconds = 0;       // normals, L, M, H, projection, Dirac assembly
  double factor_seconds = 0;         // numeric factorisation(s) of the Dirac (or cMCF) matrix
  double eigen_seconds = 0;          // inverse-iteration solves and residuals
  double poisson_seconds = 0;        // divergence, pinned-Laplacian factorisation and 3-RHS solve
  std::string note;                  // why a step was rejected, or "" when accepted
};

enum class MapStatus { Ok, NotConverged, VerificationFailed, SolverFailed };
const char* to_string(MapStatus status);

// One try of one method (the first try and each fallback).
struct MapAttempt {
  MapMethod method = MapMethod::Willmore;
  bool filtered = false;
  int max_steps = 0;
  MapStatus status = MapStatus::Ok;
  std::string failed_check;          // "flipped_faces", "degenerate_faces", "roundness", "solver", ... or empty
  std::string message;
  MapQuality quality;
  std::vector<FlowStepRecord> steps;
  double seconds = 0;
  bool hit_step_cap = false;         // Added: the flow ran out of steps (so "more steps" may help)
};

struct SphericalMapResult {
  Eigen::MatrixX3d sphere;           // #V by 3 unit vectors: the image of each input vertex
  MapStatus status = MapStatus::Ok;  // of the attempt whose map is returned
  std::string failed_check;          // empty when Ok
  MapQuality quality;
  MapMethod method_used = MapMethod::Willmore;
  std::vector<MapAttempt> attempts;  // in order; the last one produced `sphere`
  double seconds = 0;
  bool ok() const { return status == MapStatus::Ok; }
};

// Never throws for numerical trouble (that is a status); throws TimeoutError when `deadline` passes
// between flow steps, and InvalidInputError for meshes that violate the preconditions.
SphericalMapResult compute_spherical_map(const Mesh& mesh, const SphericalMapOptions& options = {},
                                         const Deadline& deadline = {});

}  // namespace wish
