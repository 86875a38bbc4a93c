#pragma once
// Unit icosphere by recursive edge subdivision of the icosahedron (the paper's reconstruction domain).
// Level 0: 12 vertices, 20 faces; level n: 10*4^n + 2 vertices, 20*4^n faces. Outward (CCW) orientation.

#include "core/mesh/mesh.hpp"

namespace wish {

Mesh make_icosphere(int level);  // level in [0, 8]; throws InvalidInputError otherwise

}  // namespace wish
