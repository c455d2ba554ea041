// What the live viewer's page is sent, built from a simulation on its thread and turned into JSON (or binary)
// on the server's: the layout (geometry, colours, bodies; again whenever robots or world models come or go),
// frames (the poses of what moves, lidar hits, sim time, RTF) and camera images.
//
// Units on the wire: metres and seconds; a pose is [x, y, z, qx, qy, qz, qw] in the world (z up); geometry
// positions are integers in units of kPositionUnit.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "bullet_sim/plugins/outputs.h"
#include "bullet_sim/simulation/simulation.h"
#include "web_server.h"

namespace bullet_sim {

constexpr double kPositionUnit = 1e-4;  ///< [m] of the geometries' integer positions

/// Something the page moves as one: a robot's link, or the frame of one visual of a world model.
struct ViewerBody {
  std::string name;    ///< "robot::link", or "model::visual_N" for a world model's
  std::string robot;   ///< "" for a world model's
  std::string link;    ///< a robot's link
  size_t model = 0;    ///< a world model's: its index in the world
  size_t visual = 0;   ///< a world model's: the visual's index in the model
  bool moves = false;  ///< a robot's link, or a visual of a non-static world model: sent in every frame
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the world, when the layout was made
};

/// One visual: a mesh in its body's frame, in its colours.
struct ViewerMesh {
  std::shared_ptr<const TriangleMesh> mesh;
  size_t body = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the body's frame
  Eigen::Vector4d rgba{0.7, 0.7, 0.7, 1};
  MeshPaint paint = MeshPaint::kOwn;
};

struct ViewerRobot {
  std::string name;
  size_t root_body = 0;  ///< the body of its root link
  bool teleop = false;   ///< it takes velocity commands (a drive's cmd_vel)
};

/// A camera the page may watch: its key is "robot/sensor".
struct ViewerCamera {
  std::string key;
  std::string robot;
  std::string sensor;  ///< the camera plugin's name
};

/// What the page draws, as it stands when robots or world models came or went.
struct ViewerLayout {
  uint64_t revision = 0;
  std::vector<ViewerBody> bodies;
  std::vector<ViewerMesh> meshes;
  std::vector<ViewerRobot> robots;
  std::vector<ViewerCamera> cameras;
  std::vector<Eigen::Isometry3d> world_model_poses;  ///< per world model, then
  Eigen::AlignedBox3d bounds;  ///< the world's obstacles and the robots, for the page's first view
  size_t max_mesh_triangles = 20000;
};

ViewerLayout viewerLayout(const Simulation& simulation, uint64_t revision, size_t max_mesh_triangles);

/// {"type": "scene", "revision", "bounds", "bodies": [{"name", "pose"}], "geometries": [{"positions",
/// "indices"}], "meshes": [{"geometry", "body", "pose", "parts": [[first triangle, count, r, g, b, a]]}],
/// "robots": [{"name", "body", "teleop"}], "cameras": [key]}. Meshes above the layout's triangle budget are
/// simplified; meshes that share a file share a geometry.
std::string sceneJson(const ViewerLayout& layout);

/// What moved: a snapshot taken after a step.
struct ViewerFrame {
  uint64_t revision = 0;  ///< of the layout whose bodies `poses` index
  double time = 0;        ///< [s] sim time
  double rtf = 0;         ///< sim seconds per wall second, lately
  bool paused = false;
  std::vector<std::pair<size_t, Eigen::Isometry3d>> poses;  ///< bodies that move or were moved
  std::vector<Eigen::Vector3f> hits;                        ///< every lidar's latest hits, in the world
};

/// The frame of `simulation` now: the poses of the bodies that move, and of world models' bodies that were
/// moved since the layout; at most `max_hits` hits, thinned evenly.
ViewerFrame viewerFrame(const Simulation& simulation, const ViewerLayout& layout, size_t max_hits);

/// {"type": "frame", "revision", "time", "rtf", "paused", "poses": [body, x, y, z, qx, qy, qz, qw, ...],
/// "hits": [x, y, z, ...]}.
std::string frameJson(const ViewerFrame& frame);

/// The latest image of a camera as one binary message: a 4-byte little-endian length N, N bytes of JSON
/// {"type": "image", "camera", "width", "height", "encoding", "step", "stamp"}, then the pixel rows as the
/// camera's ROS encoding lays them out.
std::string imageMessage(const std::string& camera, const CameraImage& image);

/// The latest image of a camera (CameraImage) that a layout lists, or nullptr when it has none yet.
const Stream<CameraImage>* cameraStream(const Simulation& simulation, const ViewerCamera& camera);

/// Marks the camera's image output as wanted, as a subscriber does, so that it renders at its rate.
void wantCamera(const Simulation& simulation, const ViewerCamera& camera);

/// Messages that the server's thread serialises, when first sent.
std::shared_ptr<const Outgoing> sceneMessage(std::shared_ptr<const ViewerLayout> layout);
std::shared_ptr<const Outgoing> frameMessage(ViewerFrame frame);
std::shared_ptr<const Outgoing> imageOutgoing(std::string camera, CameraImage image);

}  // namespace bullet_sim
