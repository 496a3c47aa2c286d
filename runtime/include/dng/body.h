// Bodies: a DN field placed in the world with a rigid transform and a uniform scale, moving or not,
// with a material that says how particles respond to it (paper §3.1: "objects can be rotated and
// translated freely ... scaled uniformly ... cannot be sheared").
#pragma once

#include "dng/format/vec3.h"
#include "dng/status.h"
#include "dng/view.h"

#include <cstdint>

namespace dng {

/// How particles bounce off a body.
enum class Response : std::uint32_t {
  kImpact = 0, ///< paper §3.4: reflect the velocity, restitution beta
  kSpring = 1, ///< paper §3.3: an acceleration along the normal growing with depth into the field
  kNone = 2,   ///< no bounce (drag and flow may still apply)
};

/// Response parameters of one body. Units: lengths in world units, time in seconds. Every field has
/// a usable default; Body::setMaterial rejects negative or non-finite values.
struct Material {
  Response response = Response::kImpact;
  /// beta, paper §3.4: 1 keeps the normal speed, 0 removes it. >= 0.
  float restitution = 0.5f;
  /// L, paper Fig. 4: slow particles bounce at this distance from the surface; fast ones as soon as
  /// they would cross it within the step. Use at least the particle radius and ~0.1 voxel.
  float collision_distance = 0.0f;
  /// Spring method: acceleration = stiffness * (spring_distance - d) along the normal, in 1/s^2.
  float spring_stiffness = 400.0f;
  /// Spring method: where the spring starts; 0 means "the field's whole band".
  float spring_distance = 0.0f;
  /// delta, paper §3.5: tangential velocity decays at this rate (1/s) within contact_distance.
  float drag = 0.0f;
  /// theta, paper §3.5: the drag's reach from the surface.
  float contact_distance = 0.0f;
  /// rho_in / rho_out, paper §3.6: tangential steering acceleration (world units/s^2) for particles
  /// moving towards (N.V < 0) / away from the surface. Negative values attract.
  float flow_in = 0.0f;
  float flow_out = 0.0f;
  /// The surface flow's reach from the surface.
  float flow_distance = 0.0f;
  /// Every step is walked through the field, so no particle tunnels at any speed (docs/RUNTIME.md).
  /// Swept bodies let the walk take up to 256 samples instead of 24, so a particle far faster than
  /// the design speed is never stopped short of where it was going; it costs only those samples.
  bool swept = false;
};

/// A placed field. Plain value type: copy it freely. Keeps a pointer to the View, which must outlive
/// every Body made from it; one View may serve any number of bodies. A View opened again on another
/// file is another field: create its bodies again (a body keeps its box from the old grid; the step
/// refuses what it cannot walk, but cannot know the box is stale).
class Body {
public:
  Body() = default;

  /// A body of `field` at the identity transform, at rest. Fails (leaving *out_body empty) when the
  /// view is not valid, its band is too thin to step through (under about 0.93 voxel: the guaranteed
  /// reach must exceed the walk's margin; dngbake writes at least 1 voxel) or the material is invalid.
  static Status create(const View* field, const Material& material, Body* out_body, Diagnostic* out_diag = nullptr);

  /// Sets the transform from a row-major 3x4 matrix [s*R | t] (local -> world). Rejects, leaving the
  /// body unchanged: non-finite entries, a scale that is zero or whose value or inverse is not a normal
  /// float, a placed box that overflows float's range, shear, non-uniform scale and reflections (they
  /// break the normals). Tolerance: 1e-4 relative.
  Status setTransform(const float row_major_3x4[12], Diagnostic* out_diag = nullptr);

  /// Same, from parts: translation, unit quaternion (w, x, y, z; normalized here), uniform scale > 0.
  Status setTransform(Vec3f translation, const float quaternion_wxyz[4], float scale, Diagnostic* out_diag = nullptr);

  /// World-frame linear velocity of the body origin and angular velocity (rad/s) about it. The
  /// transform is the body's pose at the start of a step; stepParticles moves the body on at these
  /// velocities for dt and judges each particle's motion against both poses (docs/RUNTIME.md), so
  /// set them to how the body really moves over the coming step. Any values are kept; stepParticles
  /// and BodyIndex::rebuild refuse a body whose velocities give no finite motion over their dt.
  void setVelocity(Vec3f linear, Vec3f angular) {
    linear_velocity_ = linear;
    angular_velocity_ = angular;
  }

  Status setMaterial(const Material& material, Diagnostic* out_diag = nullptr);

  bool valid() const { return field_ != nullptr; }
  const View* field() const { return field_; }
  const Material& material() const { return material_; }
  float scale() const { return scale_; }
  /// The rotation part of the transform, row-major 3x3 (orthonormal).
  const float* rotation() const { return rotation_; }
  Vec3f translation() const { return translation_; }
  Vec3f linearVelocity() const { return linear_velocity_; }
  Vec3f angularVelocity() const { return angular_velocity_; }
  /// World-space bounding box of the grid, for culling.
  Vec3f boundsMin() const { return bounds_min_; }
  Vec3f boundsMax() const { return bounds_max_; }

  /// World -> local point.
  Vec3f toLocal(Vec3f world) const {
    const Vec3f d = world - translation_;
    const float* r = rotation_; // R^T d / s
    return Vec3f{r[0] * d.x + r[3] * d.y + r[6] * d.z, r[1] * d.x + r[4] * d.y + r[7] * d.z,
                 r[2] * d.x + r[5] * d.y + r[8] * d.z} *
           inv_scale_;
  }
  /// Local -> world direction (rotation only) and point.
  Vec3f rotateToWorld(Vec3f v) const {
    const float* r = rotation_;
    return {r[0] * v.x + r[1] * v.y + r[2] * v.z, r[3] * v.x + r[4] * v.y + r[5] * v.z,
            r[6] * v.x + r[7] * v.y + r[8] * v.z};
  }
  Vec3f toWorld(Vec3f local) const { return translation_ + rotateToWorld(local * scale_); }
  /// Velocity of the body's material point at world position `p`.
  Vec3f surfaceVelocity(Vec3f p) const { return linear_velocity_ + cross(angular_velocity_, p - translation_); }
  /// Whether stepParticles can move a particle placed at the world point `p` by this body: the field
  /// proves the point outside the surface (a plane of its cell, its second bound or a neighbouring
  /// cell's bound reads at least a hundredth of a voxel there), or the point is beyond the field. A
  /// particle placed where this is false never moves (docs/RUNTIME.md, "Limits"), so an emitter can test
  /// its spawn points against each body and move them out or drop them. False for points inside and for
  /// a non-finite `p`; the answer depends on the transform, not on the velocities or the material (a
  /// Response::kNone body blocks nothing, whatever this says).
  bool provesOutside(Vec3f p) const;

private:
  void updateBounds();

  const View* field_ = nullptr;
  Material material_;
  float rotation_[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}; // row-major, orthonormal
  float scale_ = 1.0f;
  float inv_scale_ = 1.0f;
  Vec3f translation_;
  Vec3f linear_velocity_;
  Vec3f angular_velocity_;
  Vec3f bounds_min_;
  Vec3f bounds_max_;
};

} // namespace dng
