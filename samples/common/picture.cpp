#include "picture.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dng {
namespace samples {

namespace {

// March one body along the ray start + t dir, t in [t0, t1]: the first t where its field says
// distance <= 0, and the normal there. Steps by the sampled distance (sphere tracing), never less
// than a quarter voxel.
bool traceBody(const Body& body, Vec3f start, Vec3f dir, float t0, float t1, float* out_t, Vec3f* out_normal) {
  const float h = body.field()->grid().voxel_size * body.scale();
  for (float t = t0; t <= t1;) {
    const Vec3f p = start + dir * t;
    const Sample s = body.field()->sample(body.toLocal(p));
    const float d = s.status == SampleStatus::kNoField ? h : s.distance * body.scale();
    if (d <= 0.0f) {
      *out_t = t;
      *out_normal = s.status == SampleStatus::kInBand ? body.rotateToWorld(s.normal) : dir * -1.0f;
      return true;
    }
    t += std::max(0.8f * d, 0.25f * h);
  }
  return false;
}

} // namespace

Picture::Picture(Vec3f lo, Vec3f hi, int view_axis, int long_side) : lo_(lo), hi_(hi), axis_(view_axis) {
  u_ = view_axis == 0 ? 1 : 0;
  v_ = view_axis == 2 ? 1 : 2;
  const float su = component(hi - lo, u_), sv = component(hi - lo, v_);
  pixels_per_unit_ = float(long_side) / std::max(su, sv);
  width_ = std::max(1, int(su * pixels_per_unit_));
  height_ = std::max(1, int(sv * pixels_per_unit_));
  depth_.assign(std::size_t(width_) * height_, std::numeric_limits<float>::infinity());
  shade_.assign(depth_.size(), 0.0f);
  light_.assign(depth_.size(), Colour{});
}

bool Picture::project(Vec3f p, int* x, int* y, float* depth) const {
  *x = int((component(p, u_) - component(lo_, u_)) * pixels_per_unit_);
  *y = height_ - 1 - int((component(p, v_) - component(lo_, v_)) * pixels_per_unit_);
  *depth = component(hi_, axis_) - component(p, axis_);
  return *x >= 0 && *y >= 0 && *x < width_ && *y < height_;
}

void Picture::drawBodies(const std::vector<Body>& bodies) {
  const Vec3f light = normalizeOrZero({0.45f, 0.35f, 0.82f});
  Vec3f dir;
  component(dir, axis_) = -1.0f;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      float start_coords[3];
      start_coords[axis_] = component(hi_, axis_);
      start_coords[u_] = component(lo_, u_) + (float(x) + 0.5f) / pixels_per_unit_;
      start_coords[v_] = component(lo_, v_) + (float(height_ - 1 - y) + 0.5f) / pixels_per_unit_;
      const Vec3f start{start_coords[0], start_coords[1], start_coords[2]};
      const float length = component(hi_ - lo_, axis_);
      float best = std::numeric_limits<float>::infinity();
      Vec3f normal;
      for (const Body& b : bodies) {
        float t = 0.0f;
        Vec3f n;
        if (traceBody(b, start, dir, 0.0f, length, &t, &n) && t < best) best = t, normal = n;
      }
      const std::size_t i = std::size_t(y) * width_ + x;
      depth_[i] = best;
      // Lambert shading, and nearer surfaces brighter so faces with the same normal at different
      // depths (roofs over the ground) stay apart.
      if (std::isfinite(best))
        shade_[i] = (0.3f + 0.7f * std::max(0.0f, dot(normal, light))) * (1.0f - 0.45f * best / length);
    }
}

void Picture::splat(Vec3f p, Colour c, float weight) {
  int x = 0, y = 0;
  float depth = 0.0f;
  if (!project(p, &x, &y, &depth)) return;
  const std::size_t i = std::size_t(y) * width_ + x;
  if (depth > depth_[i]) return; // behind a body
  light_[i].r += c.r * weight, light_[i].g += c.g * weight, light_[i].b += c.b * weight;
}

bool Picture::write(const std::string& path) const {
  std::vector<std::uint8_t> rgb(depth_.size() * 3);
  for (std::size_t i = 0; i < depth_.size(); ++i) {
    // Background, or the body in a cool grey; particles blend over it with 1 - exp(-light).
    const bool body = std::isfinite(depth_[i]);
    const float base[3] = {body ? 0.55f * shade_[i] + 0.1f : 0.97f, body ? 0.6f * shade_[i] + 0.1f : 0.97f,
                           body ? 0.7f * shade_[i] + 0.12f : 0.97f};
    const float light[3] = {light_[i].r, light_[i].g, light_[i].b};
    const float total = light[0] + light[1] + light[2];
    const float alpha = 1.0f - std::exp(-total);
    for (int c = 0; c < 3; ++c) {
      const float tint = total > 0.0f ? light[c] / total : 0.0f;
      const float value = base[c] * (1.0f - alpha) + std::min(1.0f, tint * 1.6f) * alpha;
      rgb[i * 3 + c] = std::uint8_t(std::clamp(value, 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = png_uint_32(width_);
  image.height = png_uint_32(height_);
  image.format = PNG_FORMAT_RGB;
  return png_image_write_to_file(&image, path.c_str(), 0, rgb.data(), 0, nullptr) != 0;
}

} // namespace samples
} // namespace dng
