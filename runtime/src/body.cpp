// Body placement: transform checks and decomposition, world bounds; whether the step can move a
// particle from a point.
#include "dng/body.h"
#include "diagnostic.h"
#include "walk.h"

#include <cmath>

namespace dng {

namespace {

constexpr float kTolerance = 1e-4f;

bool allFinite(const float* values, int count) {
  for (int i = 0; i < count; ++i) {
    if (!std::isfinite(values[i])) return false;
  }
  return true;
}

bool nonNegativeFinite(float x) { return x >= 0.0f && std::isfinite(x); }

// The transform's checks in double: a float column's squared length overflows above a scale of about
// 1.8e19 and loses its precision to subnormals below about 1e-19, where the checks would pass a scale
// of infinity or a rotation that is not orthonormal.
struct Column {
  double x, y, z;
};
double dot(const Column& a, const Column& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double length(const Column& c) { return std::sqrt(dot(c, c)); }

// A scale (a column's length, never negative) the body's frames can use: it and its inverse are normal
// floats.
bool usableScale(double scale) { return std::isnormal(float(scale)) && std::isnormal(1.0f / float(scale)); }

} // namespace

Status Body::create(const View* field, const Material& material, Body* out_body, Diagnostic* out_diag) {
  if (out_body == nullptr) return writeDiagnostic(out_diag, Status::kInvalidArgument, "out_body is null");
  *out_body = Body();
  if (field == nullptr || !field->valid())
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "a body needs a valid, opened field");
  if (!walkable(*field))
    return writeDiagnostic(out_diag, Status::kInvalidArgument,
                           "the field's band (%g voxels) is too thin to step particles through: it needs more than %g",
                           double(field->grid().band / field->grid().voxel_size),
                           double(format::kHalfCubeDiagonal + kMarginVoxels));
  Body body;
  body.field_ = field;
  const Status status = body.setMaterial(material, out_diag);
  if (status != Status::kOk) return status;
  body.updateBounds();
  *out_body = body;
  return Status::kOk;
}

Status Body::setMaterial(const Material& m, Diagnostic* out_diag) {
  const float values[] = {m.restitution, m.collision_distance, m.spring_stiffness, m.spring_distance,
                          m.drag,        m.contact_distance,   m.flow_distance};
  for (float v : values) {
    if (!nonNegativeFinite(v))
      return writeDiagnostic(out_diag, Status::kInvalidArgument,
                             "material values must be finite and >= 0 (restitution, distances, stiffness, drag)");
  }
  if (!std::isfinite(m.flow_in) || !std::isfinite(m.flow_out))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "flow_in and flow_out must be finite");
  if (m.response != Response::kImpact && m.response != Response::kSpring && m.response != Response::kNone)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "unknown response %u", unsigned(m.response));
  material_ = m;
  return Status::kOk;
}

// Splits [s*R | t] into a rotation and a uniform scale, or says why it cannot.
Status Body::setTransform(const float m[12], Diagnostic* out_diag) {
  if (m == nullptr) return writeDiagnostic(out_diag, Status::kInvalidArgument, "transform is null");
  if (!allFinite(m, 12)) return writeDiagnostic(out_diag, Status::kInvalidArgument, "transform has non-finite entries");
  const Column col[3] = {{m[0], m[4], m[8]}, {m[1], m[5], m[9]}, {m[2], m[6], m[10]}};
  const double scale = length(col[0]);
  if (!usableScale(scale))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "transform scale %g is zero or out of float's range",
                           scale);
  // Shear first: it changes axis lengths too, and the message should name the real cause.
  const double lengths[3] = {scale, length(col[1]), length(col[2])};
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3;
    if (std::fabs(dot(col[a], col[b])) > kTolerance * lengths[a] * lengths[b])
      return writeDiagnostic(out_diag, Status::kInvalidArgument, "shear would break the normals");
  }
  for (int a = 1; a < 3; ++a) {
    if (std::fabs(lengths[a] - scale) > kTolerance * scale)
      return writeDiagnostic(out_diag, Status::kInvalidArgument,
                             "non-uniform scale (axis lengths %g, %g, %g) would break the normals", lengths[0],
                             lengths[1], lengths[2]);
  }
  const Column normal{col[0].y * col[1].z - col[0].z * col[1].y, col[0].z * col[1].x - col[0].x * col[1].z,
                      col[0].x * col[1].y - col[0].y * col[1].x};
  if (dot(normal, col[2]) < 0.0)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "reflection would turn the field inside out");
  Body placed = *this;
  placed.scale_ = float(scale);
  placed.inv_scale_ = 1.0f / placed.scale_;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      placed.rotation_[3 * r + c] = m[4 * r + c] * placed.inv_scale_;
  placed.translation_ = {m[3], m[7], m[11]};
  placed.updateBounds();
  if (field_ != nullptr && !(isFinite(placed.bounds_min_) && isFinite(placed.bounds_max_)))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "the transformed field's box overflows float's range");
  *this = placed;
  return Status::kOk;
}

Status Body::setTransform(Vec3f t, const float q[4], float scale, Diagnostic* out_diag) {
  if (q == nullptr) return writeDiagnostic(out_diag, Status::kInvalidArgument, "quaternion is null");
  if (!allFinite(q, 4)) return writeDiagnostic(out_diag, Status::kInvalidArgument, "quaternion must be finite");
  const Column v{q[1], q[2], q[3]};
  const double len = std::sqrt(double(q[0]) * q[0] + dot(v, v));
  if (!(len > 0.0)) return writeDiagnostic(out_diag, Status::kInvalidArgument, "quaternion must be non-zero");
  const float w = float(q[0] / len), x = float(q[1] / len), y = float(q[2] / len), z = float(q[3] / len);
  const float r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                      2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                      2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  const float m[12] = {scale * r[0], scale * r[1], scale * r[2], t.x,          scale * r[3], scale * r[4],
                       scale * r[5], t.y,          scale * r[6], scale * r[7], scale * r[8], t.z};
  return setTransform(m, out_diag);
}

bool Body::provesOutside(Vec3f p) const {
  if (field_ == nullptr || !isFinite(p)) return false;
  return walkProvesOutside(*field_, toLocal(p)); // the step's start-of-step frame is the transform's
}

void Body::updateBounds() {
  if (field_ == nullptr) return;
  const GridInfo& g = field_->grid();
  const Vec3f lo = g.origin;
  const Vec3f size{float(g.dims[0]) * g.voxel_size, float(g.dims[1]) * g.voxel_size, float(g.dims[2]) * g.voxel_size};
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3f p =
        toWorld(lo + Vec3f{corner & 1 ? size.x : 0.0f, corner & 2 ? size.y : 0.0f, corner & 4 ? size.z : 0.0f});
    bounds_min_ = corner == 0 ? p
                              : Vec3f{std::fmin(bounds_min_.x, p.x), std::fmin(bounds_min_.y, p.y),
                                      std::fmin(bounds_min_.z, p.z)};
    bounds_max_ = corner == 0 ? p
                              : Vec3f{std::fmax(bounds_max_.x, p.x), std::fmax(bounds_max_.y, p.y),
                                      std::fmax(bounds_max_.z, p.z)};
  }
}

} // namespace dng
