// The members of the mesh types, listed once for byte_codec.h: what a child process that imports a mesh sends
// back.
#pragma once

#include "bullet_sim/assets/mesh.h"

namespace bullet_sim {

template <class A>
void fields(A& a, Texture& t) {
  a(t.width, t.height, t.rgba, t.source);
}
template <class A>
void fields(A& a, MeshMaterial& m) {
  a(m.rgba, m.texture);
}
template <class A>
void fields(A& a, MeshPart& p) {
  a(p.first_triangle, p.triangle_count, p.material);
}
template <class A>
void fields(A& a, TriangleMesh& m) {
  a(m.vertices, m.triangles, m.uvs, m.materials, m.parts, m.closed);
}

}  // namespace bullet_sim
