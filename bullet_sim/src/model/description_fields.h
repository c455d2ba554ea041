// The members of the description types, listed once for byte_codec.h: what a child process that reads a world
// or a model sends back.
#pragma once

#include "assets/mesh_fields.h"
#include "bullet_sim/model/world.h"

namespace bullet_sim {

template <class A>
void fields(A& a, Shape& s) {
  a(s.type, s.box_size, s.radius, s.length, s.plane_normal, s.mesh_path, s.mesh_scale, s.mesh);
}
template <class A>
void fields(A& a, Collision& c) {
  a(c.origin, c.shape, c.name, c.mu);
}
template <class A>
void fields(A& a, Visual& v) {
  a(v.origin, v.shape, v.rgba, v.material, v.paint);
}
template <class A>
void fields(A& a, InertialSpec& i) {
  a(i.mass, i.com, i.inertia);
}
template <class A>
void fields(A& a, SurfaceSpec& s) {
  a(s.mu1, s.mu2, s.kp, s.kd);
}
template <class A>
void fields(A& a, WorldLinkSpec& l) {
  a(l.name, l.pose, l.collisions, l.inertial, l.gravity, l.self_collide, l.surface, l.collision_indices,
    l.visual_indices);
}
template <class A>
void fields(A& a, WorldJointSpec& j) {
  a(j.name, j.type, j.parent, j.child, j.pose, j.axis, j.lower, j.upper, j.effort, j.velocity, j.damping,
    j.friction);
}
template <class A>
void fields(A& a, TagNode& t) {
  a(t.name, t.attributes, t.text, t.children, t.line);
}
template <class A>
void fields(A& a, SensorDeclaration& s) {
  a(s.name, s.type, s.link, s.pose, s.update_rate);
}
template <class A>
void fields(A& a, PluginElement& p) {
  a(p.plugin, p.sensor, p.sensor_tags, p.where);
}
template <class A>
void fields(A& a, WorldModelSpec& m) {
  a(m.name, m.pose, m.is_static, m.allow_auto_disable, m.collisions, m.visuals, m.links, m.joints, m.plugins);
}
template <class A>
void fields(A& a, SphericalCoordinates& c) {
  a(c.latitude, c.longitude, c.elevation, c.heading);
}
template <class A>
void fields(A& a, OdeSettings& o) {
  a(o.iters, o.precon_iters, o.sor, o.cfm, o.erp, o.contact_max_correcting_vel, o.contact_surface_layer,
    o.max_contacts);
}
template <class A>
void fields(A& a, WorldSpec& w) {
  a(w.source, w.name, w.gravity, w.max_step_size, w.real_time_factor, w.real_time_update_rate, w.ode,
    w.models, w.spherical_coordinates);
}

}  // namespace bullet_sim
