// Step trace of ONE flow per mesh, without fallback and without the local repair (issue 24 item 3: why the flows
// stop at their first steps on decimated, needle-heavy meshes):
//   flow_trace_bench [--method willmore|cmcf] [--laplacian intrinsic_delaunay|mollified|extrinsic] FILE...
// Per mesh: operator statistics of the input (negative cotan weights before / after the intrinsic flips, flips),
// then per step try: tau, Willmore energy, roundness, accepted or the rejection reason; then how the attempt ended
// (stop, flips and degenerate faces of the radial projection before any repair, K p99).
#include <cstdio>
#include <string>
#include <vector>

#include "core/io/mesh_io.hpp"
#include "core/spherical_map/spherical_map.hpp"
#include "core/validation/mesh_report.hpp"

int main(int argc, char** argv) {
  wish::SphericalMapOptions options;
  options.fallback = false;
  options.untangle = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--method" && i + 1 < argc) options.method = wish::map_method_from_name(argv[++i]);
    else if (a == "--laplacian" && i + 1 < argc) options.laplacian.kind = wish::geometry::laplacian_kind_from_name(argv[++i]);
    else files.push_back(a);
  }
  for (const std::string& f : files) {
    const wish::PreparedMesh prepared = wish::prepare_for_mapping(wish::read_mesh_file(f).mesh);
    if (!prepared.mappable()) {
      std::printf("%s: refused (%s)\n", f.c_str(), prepared.issues.front().code.c_str());
      continue;
    }
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
