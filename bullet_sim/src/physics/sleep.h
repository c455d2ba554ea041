// Bodies at rest sleep as Gazebo's do (ODE's auto-disable), and what changes under a sleeper wakes it.
#pragma once

#include <vector>

#include "bullet_sim/model/model.h"

class btCollisionObject;
class btMultiBody;
class btMultiBodyDynamicsWorld;

namespace bullet_sim {

// Gazebo's ODE auto-disable (ODEPhysics::Load): a body sleeps after 1 s with its speeds under 0.1 m/s and
// 0.1 rad/s.
constexpr double kSleepSpeed = 0.1;         // [m/s] and [rad/s]
constexpr double kSleepTime = 1.0;          // [s]
/// Bullet's multibodies sum the squares of both speeds: this keeps every sleeper under both of Gazebo's.
constexpr double kMultiBodySleepMotion = kSleepSpeed * kSleepSpeed;  // [m^2/s^2]

/// Gazebo lets a body sleep (ODELink::Init) when its model allows it (<allow_auto_disable>), has no joints
/// (a URDF's fixed joints are lumped away) and no sensors; here also no plugins, which may move it.
bool maySleep(const ModelSpec& spec);

/// Wakes `body` (Bullet's deactivation) so that the next step moves it.
void wake(btMultiBody& body);
/// Wakes every body of `world`: after a change every sleeper feels (gravity).
void wakeSleepers(btMultiBodyDynamicsWorld& world);
/// Wakes the bodies in contact with any of `objects`, before those go or move: what rests on them falls.
void wakeTouching(btMultiBodyDynamicsWorld& world, const std::vector<const btCollisionObject*>& objects);

}  // namespace bullet_sim
