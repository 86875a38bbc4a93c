#pragma once
// Midpoint subdivision of a triangle mesh (every triangle split into four at its edge midpoints; the new vertices
// stay ON the old triangles): the same surface, four times as many faces per level. For the metamorphic tests of the
// descriptor (issue 37; what a descriptor must not depend on): a shape at 252 and at 4,002 vertices of
// identical geometry must give the same ξ.

#include "core/mesh/mesh.hpp"

namespace wish {

// `levels` ≥ 0 rounds of 1→4 splitting; vertices of the input keep their indices (new ones are appended), faces keep
// their orientation. Throws InvalidInputError for levels outside [0, 6].
Mesh subdivide_midpoint(const Mesh& mesh, int levels = 1);

}  // namespace wish
