#pragma once
// The triangle mesh every stage works on (libigl conventions):
//   vertices  #V by 3, double, positions in the input's units (for nuclei: µm or nm, whatever the file says);
//   faces     #F by 3, int, 0-based vertex indices, counter-clockwise seen from outside (outward orientation).

#include <Eigen/Core>

namespace wish {

struct Mesh {
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX3i faces;

  Eigen::Index vertex_count() const { return vertices.rows(); }
  Eigen::Index face_count() const { return faces.rows(); }
};

}  // namespace wish
