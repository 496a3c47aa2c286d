// dngdump --slice: a slice of the field as a picture, after the paper's Figure 1 ("each arrow
// represents the direction of the normal vector N at that point and color indicates distance from
// the surface (darker is closer)"), plus the zero contour so the surface itself is visible.
#include "dump.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <unistd.h>

namespace dng {
namespace dump {

namespace {

struct Rgb {
  std::uint8_t r, g, b;
};

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;
  void set(int x, int y, Rgb c) {
    if (x >= 0 && y >= 0 && x < width && y < height) pixels[std::size_t(y) * width + x] = c;
  }
};

constexpr Rgb kContour{0, 0, 0};
constexpr Rgb kArrow{25, 25, 35};
constexpr Rgb kFarOutside{225, 225, 225};
constexpr Rgb kFarInside{196, 208, 236};

// Inside blue, outside orange; darker closer to the surface; beyond the band pale blue or grey.
Rgb distanceColour(const Sample& s, float band) {
  if (s.status == SampleStatus::kNoField) return {255, 255, 255};
  if (s.status == SampleStatus::kFarOutside) return kFarOutside;
  if (s.status == SampleStatus::kFarInside) return kFarInside;
  const float t = 0.3f + 0.7f * std::min(std::fabs(s.distance) / band, 1.0f);
  return s.distance < 0.0f ? Rgb{std::uint8_t(60 * t), std::uint8_t(120 * t), std::uint8_t(255 * t)}
                           : Rgb{std::uint8_t(255 * t), std::uint8_t(150 * t), std::uint8_t(40 * t)};
}

void drawLine(Image& image, float x0, float y0, float x1, float y1, Rgb colour) {
  const int steps = int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))) + 1;
  for (int i = 0; i <= steps; ++i) {
    const float t = float(i) / float(steps);
    image.set(int(std::lround(x0 + (x1 - x0) * t)), int(std::lround(y0 + (y1 - y0) * t)), colour);
  }
}

void drawArrow(Image& image, float x, float y, float dx, float dy) {
  const float x1 = x + dx, y1 = y + dy;
  drawLine(image, x, y, x1, y1, kArrow);
  // Head: two strokes back from the tip at +-150 degrees.
  for (float side : {1.0f, -1.0f}) {
    const float c = std::cos(2.6f), s = side * std::sin(2.6f);
    drawLine(image, x1, y1, x1 + 0.35f * (c * dx - s * dy), y1 + 0.35f * (s * dx + c * dy), kArrow);
  }
}

// The slice plane's two image axes (grid axes), the image's y pointing up along the second.
void imageAxes(int axis, int* out_u, int* out_v) {
  *out_u = axis == 0 ? 1 : 0;
  *out_v = axis == 2 ? 1 : 2;
}

bool writePng(const Image& image, const std::string& path) {
  const std::string temp = path + ".tmp." + std::to_string(::getpid());
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGB;
  if (png_image_write_to_file(&png, temp.c_str(), 0, image.pixels.data(), 0, nullptr) &&
      std::rename(temp.c_str(), path.c_str()) == 0)
    return true;
  std::remove(temp.c_str());
  return false;
}

} // namespace

int renderSlice(const View& view, const SliceRequest& request) {
  const GridInfo& g = view.grid();
  int au = 0, av = 0;
  imageAxes(request.axis, &au, &av);
  const int nu = int(g.dims[au]), nv = int(g.dims[av]);
  const float lo = component(g.origin, request.axis);
  if (!(request.value >= lo && request.value < lo + float(g.dims[request.axis]) * g.voxel_size)) {
    std::fprintf(stderr, "dngdump: error: the slice %c=%g lies outside the grid [%g, %g)\n", "xyz"[request.axis],
                 double(request.value), double(lo), double(lo + float(g.dims[request.axis]) * g.voxel_size));
    return tools::kExitUsage;
  }
  const int scale = request.scale > 0 ? request.scale : std::clamp(768 / std::max(nu, nv), 1, 16);
  // A grid may be 2^24 voxels long: refuse a picture that size rather than fail to allocate it.
  if (std::int64_t(std::max(nu, nv)) * scale > kMaxSlicePixels) {
    std::fprintf(stderr, "dngdump: error: a %d x %d voxel slice at %d pixels per voxel exceeds %d pixels per side\n",
                 nu, nv, scale, kMaxSlicePixels);
    return tools::kExitUnsupported;
  }
  Image image;
  image.width = nu * scale;
  image.height = nv * scale;
  image.pixels.assign(std::size_t(image.width) * image.height, Rgb{255, 255, 255});
  // Pixel (x, y) shows the point at its centre; image y grows downwards, the grid axis upwards.
  auto pointAt = [&](float x, float y) {
    float p[3] = {g.origin.x, g.origin.y, g.origin.z};
    p[request.axis] = request.value;
    p[au] += x / float(scale) * g.voxel_size;
    p[av] += (float(image.height) - y) / float(scale) * g.voxel_size;
    return Vec3f{p[0], p[1], p[2]};
  };
  std::vector<float> signs(image.pixels.size());
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Sample s = view.sample(pointAt(float(x) + 0.5f, float(y) + 0.5f));
      image.pixels[std::size_t(y) * image.width + x] = distanceColour(s, g.band);
      signs[std::size_t(y) * image.width + x] = s.status == SampleStatus::kNoField ? 0.0f : s.distance;
    }
  for (int y = 0; y + 1 < image.height; ++y) // the zero contour: a sign change to the right or below
    for (int x = 0; x + 1 < image.width; ++x) {
      const float d = signs[std::size_t(y) * image.width + x];
      if ((d < 0.0f) != (signs[std::size_t(y) * image.width + x + 1] < 0.0f) ||
          (d < 0.0f) != (signs[std::size_t(y + 1) * image.width + x] < 0.0f))
        image.set(x, y, kContour);
    }
  const int step = std::max(1, (14 + scale - 1) / scale); // an arrow every ~14 pixels
  for (int v = step / 2; v < nv; v += step)
    for (int u = step / 2; u < nu; u += step) {
      const float x = (float(u) + 0.5f) * float(scale), y = float(image.height) - (float(v) + 0.5f) * float(scale);
      const Sample s = view.sample(pointAt(x, y));
      if (s.status != SampleStatus::kInBand) continue;
      const float length = 0.45f * float(step * scale);
      drawArrow(image, x, y, component(s.normal, au) * length, -component(s.normal, av) * length);
    }
  if (!writePng(image, request.png)) {
    std::fprintf(stderr, "dngdump: error: cannot write '%s'\n", request.png.c_str());
    return tools::kExitIo;
  }
  return tools::kExitOk;
}

} // namespace dump
} // namespace dng
