#include "physics/sleep.h"

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <utility>

namespace bullet_sim {

bool maySleep(const ModelSpec& spec) {
  const auto joined = [&](const JointSpec& joint) { return spec.names_from_sdf || joint.moves(); };
  return spec.allow_auto_disable && !spec.is_static && spec.plugins.empty() &&
         std::none_of(spec.joints.begin(), spec.joints.end(), joined);
}

namespace {
/// Wakes a rigid body or a multibody's link; static objects stay as they are.
void wakeObject(const btCollisionObject& object) {
  if (const auto* link = btMultiBodyLinkCollider::upcast(&object)) {
    wake(*link->m_multiBody);
  } else if (const btRigidBody* body = btRigidBody::upcast(&object); body && !body->isStaticObject()) {
    const_cast<btRigidBody*>(body)->activate();  // the manifolds hand out bodies as const
  }
}
}  // namespace

void wake(btMultiBody& body) {
  if (!body.getCanSleep()) return;
  body.wakeUp();
  // Bullet reactivates a woken body's colliders only after the next step: this one would skip it.
  const auto activate = [](btMultiBodyLinkCollider* collider) {
    if (collider && collider->getActivationState() != DISABLE_DEACTIVATION) collider->activate(true);
  };
  activate(body.getBaseCollider());
  for (int link = 0; link < body.getNumLinks(); ++link) activate(body.getLink(link).m_collider);
}

void wakeSleepers(btMultiBodyDynamicsWorld& world) {
  for (int k = 0; k < world.getNumMultibodies(); ++k) wake(*world.getMultiBody(k));
  btAlignedObjectArray<btRigidBody*>& bodies = world.getNonStaticRigidBodies();
  for (int k = 0; k < bodies.size(); ++k) bodies[k]->activate();
}

void wakeTouching(btMultiBodyDynamicsWorld& world, const std::vector<const btCollisionObject*>& objects) {
  const auto listed = [&](const btCollisionObject* object) {
    return std::find(objects.begin(), objects.end(), object) != objects.end();
  };
  btDispatcher& dispatcher = *world.getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    if (manifold.getNumContacts() == 0) continue;
    for (const auto& [one, other] : {std::pair(manifold.getBody0(), manifold.getBody1()),
                                     std::pair(manifold.getBody1(), manifold.getBody0())}) {
      if (listed(one)) wakeObject(*other);
    }
  }
}

}  // namespace bullet_sim
