// A picture of a robot in a world as the simulator sees it, after its lidars have scanned: what render_model
// draws. Links the simulator core (Bullet) and the renderer's scene; ROS-free.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/scene/camera.h"
#include "bullet_sim/scene/image.h"
#include "bullet_sim/scene/scene.h"
#include "bullet_sim/scene/scene_renderer.h"
#include "bullet_sim/simulation/simulation.h"

namespace bullet_sim {

struct RobotSnapshot {
  Scene scene;                        ///< the camera is set for the view
  std::vector<std::string> warnings;  ///< from spawning, and about lidars that did not scan in time
};

/// Spawns `model` into a simulation of `world` at `pose` (resting on the ground unless pose.z is given),
/// steps until each of its lidars has produced a scan, for at most kSnapshotMaxSimTime of sim time, and
/// builds the scene: the world, the ground grid, the robot at its link poses in its colours, and each lidar's
/// hits as red 4 px dots. Throws SpecError when the robot cannot be spawned.
RobotSnapshot snapshotRobot(WorldSpec world, ModelSpec model, const SpawnPose& pose, View view);

constexpr double kSnapshotMaxSimTime = 1.0;  ///< [s]

/// The scene of a running simulation: the world, every robot at its link poses in its colours, every lidar's
/// latest hits as red dots, and `trails` (e.g. odometry); the camera is set for `view` around the robot named
/// `focus` (the first robot when it names none). Lidars that have not scanned yet add no hits.
Scene simulationScene(const Simulation& simulation, View view, const std::string& focus = "",
                      const std::vector<Polyline>& trails = {});

/// A view through a robot's camera: "camera:NAME" (its image) or "depth:NAME" (its depth, grey: white near,
/// black at the far end of its range or where nothing is seen). NAME is the <sensor> name or the cameraName.
struct CameraView {
  std::string camera;
  bool depth = false;
};

/// The camera view a name asks for; nullopt when the name is not "camera:NAME" or "depth:NAME".
std::optional<CameraView> parseCameraView(const std::string& name);

/// What the camera of `view` sees now, at its own size. Throws std::invalid_argument naming the cameras there
/// are when no robot has that camera, or when a depth view asks a camera without depth.
Image cameraImage(const Simulation& simulation, const CameraView& view, SceneRenderer& renderer);

/// snapshotRobot for a camera view: the robot settles for kSnapshotMaxSimTime, then its camera draws.
Image snapshotCamera(WorldSpec world, ModelSpec model, const SpawnPose& pose, const CameraView& view,
                     SceneRenderer& renderer, std::vector<std::string>* warnings);

}  // namespace bullet_sim
