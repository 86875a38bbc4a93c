// Step trace of ONE flow per mesh, without fallback and without the local repair (issue 24 item 3: why the flows
// stop at their first steps on decimated, needle-heavy meshes):
//   flow_trace_bench [--method willmore|cmcf] [--laplacian intrinsic_delaunay|mollified|extrinsic] [--cmcf-delta D]
//                    [--steps N] [--needle] [--roundness-stall S] [--energy-tolerance E] FILE...
// (--needle: Willmore with the needle operator, WillmoreOptions::needle_operator; the other two: its stop rules)
// Per mesh: operator statistics of the input (negative cotan weights before / after the intrinsic flips, flips),
// then per step try: tau, Willmore energy, roundness, accepted or the rejection reason; then how the attempt ended
// (stop, flips and degenerate faces of the radial projection before any repair, K p99). First, the default chain's
// map of the mesh: its K p99 over all faces, over the faces with every angle >= 5 degrees and over the needles.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/io/mesh_io.hpp"
#include "core/spherical_map/map_verification.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

namespace {

// Smallest corner angle of each face, in degrees.
std::vector<double> smallest_angles(const wish::Mesh& m) {
  std::vector<double> out(static_cast<size_t>(m.face_count()));
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    double least = 180;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = m.vertices.row(m.faces(f, k)), q = m.vertices.row(m.faces(f, (k + 1) % 3)),
                            r = m.vertices.row(m.faces(f, (k + 2) % 3));
      const double c = (q - p).normalized().dot((r - p).normalized());
      least = std::min(least, std::acos(std::clamp(c, -1.0, 1.0)) * 180 / 3.141592653589793);
    }
    out[static_cast<size_t>(f)] = least;
  }
  return out;
}

double p99(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(0.99 * static_cast<double>(v.size() - 1) + 0.5)];
}

// K p99 of the DEFAULT chain's map over all faces, over the faces with every angle >= 5 degrees, and over the
// needles (an angle under 5 degrees): how much of the figure the needle faces make.
void print_chain_distortion(const std::string& file, const wish::Mesh& mesh) {
  const wish::SphericalMapResult r = wish::compute_spherical_map(mesh);
  const wish::spherical::FaceDistortion d = wish::spherical::face_distortion(mesh.vertices, mesh.faces, r.sphere);
  const std::vector<double> angles = smallest_angles(mesh);
  std::vector<double> all, wide, needle;
  for (size_t f = 0; f < angles.size(); ++f) {
    const double k = d.conformal[static_cast<Eigen::Index>(f)];
    all.push_back(k);
    (angles[f] < 5 ? needle : wide).push_back(k);
  }
  std::printf("%s default chain: %s, flips %ld, K p99 all faces %.3g, faces with all angles >= 5 deg %.3g, needles "
              "(%zu) %.3g\n",
              file.c_str(), wish::to_string(r.method_used), r.quality.flipped_faces, p99(all), p99(wide),
              needle.size(), p99(needle));
}

}  // namespace

int main(int argc, char** argv) {
  wish::SphericalMapOptions options;
  options.fallback = false;
  options.untangle = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--method" && i + 1 < argc) options.method = wish::map_method_from_name(argv[++i]);
    else if (a == "--laplacian" && i + 1 < argc) options.laplacian.kind = wish::geometry::laplacian_kind_from_name(argv[++i]);
    else if (a == "--cmcf-delta" && i + 1 < argc) options.cmcf.delta = std::stod(argv[++i]);
    else if (a == "--steps" && i + 1 < argc) options.cmcf.max_steps = options.willmore.max_steps = std::stoi(argv[++i]);
    else if (a == "--needle") options.willmore.needle_operator = true;  // the chain's needle retry's operator
    else if (a == "--roundness-stall" && i + 1 < argc) options.willmore.roundness_stall = std::stod(argv[++i]);
    else if (a == "--energy-tolerance" && i + 1 < argc) options.willmore.energy_tolerance = std::stod(argv[++i]);
    else files.push_back(a);
  }
  for (const std::string& f : files) {
    const wish::PreparedMesh prepared = wish::prepare_for_mapping(wish::read_mesh_file(f).mesh);
    if (!prepared.mappable()) {
      std::printf("%s: refused (%s)\n", f.c_str(), prepared.issues.front().code.c_str());
      continue;
    }
    print_chain_distortion(f, prepared.mesh);
    const wish::SphericalMapResult r = wish::compute_spherical_map(prepared.mesh, options);
    for (const wish::MapAttempt& a : r.attempts) {
      const auto& s = a.operator_stats;
      std::printf("%s V=%ld %s: negative weights %ld -> %ld, intrinsic flips %ld, mollified faces %ld\n", f.c_str(),
                  static_cast<long>(prepared.mesh.vertex_count()), wish::to_string(a.method), s.negative_weights_before,
                  s.negative_weights_after, s.flips, s.mollified_faces);
      for (const wish::FlowStepRecord& st : a.steps)
        std::printf("  step %2d tau %.3f E %.4g R %.4g %s\n", st.step, st.tau, st.energy, st.roundness,
                    st.accepted ? "accepted" : ("rejected: " + st.note).c_str());
      std::printf("  end: %s, flips %ld degenerate %ld degree %d K p99 %.3g (%s)\n", wish::to_string(a.stop),
                  a.quality.flipped_faces, a.quality.degenerate_faces, a.quality.degree, a.quality.conformal_p99,
                  a.message.c_str());
    }
  }
  return 0;
}
