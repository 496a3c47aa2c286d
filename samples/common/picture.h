// Pictures for the samples: an orthographic view of a box of the world, with the bodies drawn by
// sphere tracing their own DN fields (so a sample needs nothing but the runtime to show the object)
// and particles splatted on top as trails, hidden where a body is in front of them.
#pragma once

#include "dng/body.h"

#include <string>
#include <vector>

namespace dng {
namespace samples {

struct Colour {
  float r = 0, g = 0, b = 0;
};

class Picture {
public:
  /// Looks at the box [lo, hi] along -view_axis (0 x, 1 y, 2 z): the camera sits on the + side.
  /// Image axes: view z -> (x right, y up); view y -> (x right, z up); view x -> (y right, z up).
  Picture(Vec3f lo, Vec3f hi, int view_axis, int long_side_pixels);

  /// Draws the bodies' surfaces, shaded by their field normals.
  void drawBodies(const std::vector<Body>& bodies);
  /// Adds a particle at `p` to the picture (call it every step for trails).
  void splat(Vec3f p, Colour colour, float weight = 0.15f);
  /// Writes a PNG; false when the file cannot be written.
  bool write(const std::string& path) const;

  int width() const { return width_; }
  int height() const { return height_; }

private:
  bool project(Vec3f p, int* out_x, int* out_y, float* out_depth) const;

  Vec3f lo_, hi_;
  int axis_, u_, v_;
  int width_, height_;
  float pixels_per_unit_;
  std::vector<float> depth_;  // along the view direction; +inf where no body
  std::vector<float> shade_;  // body shading in [0, 1]
  std::vector<Colour> light_; // accumulated particle light
};

} // namespace samples
} // namespace dng
