// The Python program ConvexDecomposer runs as `python3 -c`: it splits a mesh into convex parts with CoACD.
#pragma once

namespace bullet_sim {

/// Reads a mesh on stdin (little-endian: u64 vertex count, u64 triangle count, f64 x y z per vertex, i32 a b
/// c per triangle) and writes its convex parts on stdout (u64 part count, then per part u64 point count and
/// f64 x y z per point of its hull). argv[1] is the most parts. Exit status 3: CoACD (or numpy) is not
/// installed; any other failure: a traceback on stderr.
constexpr const char* kCoacdProgram = R"PY(
import os, struct, sys
# One thread: the simulator runs one process per core side by side, and CoACD's OpenMP threads, more than the
# cores, wait on each other (a 10,000-triangle mesh took 24 s instead of 10 s on a busy machine).
os.environ["OMP_NUM_THREADS"] = "1"
try:
    import numpy as np
    import coacd
except ImportError as missing:
    sys.stderr.write(str(missing))
    sys.exit(3)
answer = os.fdopen(os.dup(1), "wb")
os.dup2(2, 1)  # whatever CoACD prints goes to stderr, not into the answer
data = sys.stdin.buffer.read()
vertex_count, triangle_count = struct.unpack_from("<QQ", data)
vertices = np.frombuffer(data, "<f8", vertex_count * 3, 16).reshape(-1, 3)
triangles = np.frombuffer(data, "<i4", triangle_count * 3, 16 + 24 * vertex_count).reshape(-1, 3)
coacd.set_log_level("error")
# Cheaper than CoACD's defaults, so that an arm's first spawn takes seconds, not minutes: a coarser concavity
# (0.1 of the mesh's size, not 0.05), a coarser manifold remesh (30 voxels, not 50) and concavity sampling
# (1000 points, not 2000), and a shallower tree search (10 iterations of 10 nodes, 2 deep; not 150 of 20, 3
# deep): 4 to 10 times less CPU on a UR5's and a Kinova Gen3's meshes, whose farthest part corner lies as far
# from the mesh as before (docs/performance.md, "First spawn of a mesh arm", has the table).
parts = coacd.run_coacd(coacd.Mesh(vertices, triangles), threshold=0.1, max_convex_hull=int(sys.argv[1]),
                        preprocess_resolution=30, resolution=1000, mcts_nodes=10, mcts_iterations=10,
                        mcts_max_depth=2, seed=0)
answer.write(struct.pack("<Q", len(parts)))
for points, _ in parts:
    points = np.ascontiguousarray(points, "<f8")
    answer.write(struct.pack("<Q", len(points)) + points.tobytes())
answer.close()
)PY";

}  // namespace bullet_sim
