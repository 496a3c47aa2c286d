#include "swarm.h"

namespace dng {
namespace testing {

void Swarm::add(Vec3f p, Vec3f v) {
  px.push_back(p.x), py.push_back(p.y), pz.push_back(p.z);
  vx.push_back(v.x), vy.push_back(v.y), vz.push_back(v.z);
  contact.push_back(0), body.push_back(-1);
}

ParticleSpan Swarm::span() {
  ParticleSpan s;
  s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
  s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
  s.count = size();
  s.out_contact = contact.data();
  s.out_body = body.data();
  return s;
}

} // namespace testing
} // namespace dng
