// The incidental parts the picture-making samples share, so that each sample's own file holds only its
// scene: the command line, the exit code, and PNG pictures of particle trails. Nothing here steps
// particles or touches a field's data beyond sampling it to draw the bodies. Header-only; needs libpng.
//
// Command line: positional arguments, and anywhere among them
//   --particles N   about N particles instead of the sample's full size (the tests run small scenes)
//   --no-pictures   no PNG files (drawing the bodies takes most of a full-size run's time)
//
// Pictures: an orthographic view of a box of the world. Bodies are drawn by sphere tracing their own DN
// fields (so a sample needs nothing but the runtime to show its object); particles are splatted on top
// as light, hidden where a body is in front of them.
#pragma once

#include "dng/body.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace dng {
namespace samples {

// ---------------------------------------------------------------------------------------------------
// Errors

/// Stops the sample with exit code 2 and the call's message when a runtime call failed. A body the
/// runtime refused would let every particle fall past it, and a figure would count nothing and pass.
inline void require(Status status, const Diagnostic& diag) {
  if (status == Status::kOk) return;
  std::fprintf(stderr, "error: %s\n", diag.message);
  std::exit(2);
}

/// The exit code a sample ends with: its verdict (0, or 1 when a particle ended inside), or else 2 when
/// something it wrote was lost: a picture (`files_written` false) or its JSON lines on standard output
/// (a full disk). Flushes standard output to know.
inline int exitCode(int verdict, bool files_written) {
  const bool printed = std::fflush(stdout) == 0 && !std::ferror(stdout);
  static bool said = false; // the error stays set: a figure of several variants says it once
  if (!printed && !said) std::fprintf(stderr, "cannot write to standard output\n");
  said = said || !printed;
  return verdict != 0 ? verdict : files_written && printed ? 0 : 2;
}

// ---------------------------------------------------------------------------------------------------
// Command line

struct CommandLine {
  std::vector<std::string> positional; ///< the arguments that are not options, argv[0] excluded
  int particles = 0;                   ///< --particles; 0: the sample's full size
  bool pictures = true;                ///< false with --no-pictures

  /// positional[index], or `fallback` when there are fewer arguments.
  std::string get(std::size_t index, const std::string& fallback) const {
    return index < positional.size() ? positional[index] : fallback;
  }
};

/// Splits argv into options and positional arguments. Prints "usage: PROGRAM <usage>" and exits with
/// code 1 on an unknown option, a --particles that is not a positive number, or a positional count
/// outside [min_positional, max_positional].
inline CommandLine parseCommandLine(int argc, char** argv, std::size_t min_positional, std::size_t max_positional,
                                    const char* usage) {
  CommandLine line;
  bool ok = true;
  for (int a = 1; a < argc && ok; ++a) {
    if (std::strcmp(argv[a], "--no-pictures") == 0) {
      line.pictures = false;
    } else if (std::strcmp(argv[a], "--particles") == 0 && a + 1 < argc) {
      char* end = nullptr;
      const long n = std::strtol(argv[++a], &end, 10);
      ok = *end == '\0' && n > 0 && n <= 100000000;
      line.particles = int(n);
    } else if (std::strncmp(argv[a], "--", 2) == 0) {
      ok = false;
    } else {
      line.positional.push_back(argv[a]);
    }
  }
  if (!ok || line.positional.size() < min_positional || line.positional.size() > max_positional) {
    std::fprintf(stderr, "usage: %s %s [--particles N] [--no-pictures]\n", argv[0], usage);
    std::exit(1);
  }
  return line;
}

/// `folder`, created when missing (pictures and other output go there).
inline std::string outputFolder(const std::string& folder) {
  std::filesystem::create_directories(folder);
  return folder;
}

// ---------------------------------------------------------------------------------------------------
// Pictures

struct Colour {
  float r = 0, g = 0, b = 0;
};

/// One view of the world box [lo, hi] along -view_axis (0 x, 1 y, 2 z): the camera sits on the + side.
/// Image axes: view z -> (x right, y up); view y -> (x right, z up); view x -> (y right, z up).
class Picture {
public:
  Picture(Vec3f lo, Vec3f hi, int view_axis, int long_side_pixels) : lo_(lo), hi_(hi), axis_(view_axis) {
    u_ = view_axis == 0 ? 1 : 0;
    v_ = view_axis == 2 ? 1 : 2;
    const float su = component(hi - lo, u_), sv = component(hi - lo, v_);
    pixels_per_unit_ = float(long_side_pixels) / std::max(su, sv);
    width_ = std::max(1, int(su * pixels_per_unit_));
    height_ = std::max(1, int(sv * pixels_per_unit_));
    depth_.assign(std::size_t(width_) * height_, std::numeric_limits<float>::infinity());
    shade_.assign(depth_.size(), 0.0f);
    light_.assign(depth_.size(), Colour{});
  }

  /// Draws the bodies' surfaces, Lambert-shaded by their field normals, nearer surfaces brighter (so
  /// faces with the same normal at different depths, roofs over the ground, stay apart).
  void drawBodies(const std::vector<Body>& bodies) {
    const Vec3f light = normalizeOrZero({0.45f, 0.35f, 0.82f});
    Vec3f dir;
    component(dir, axis_) = -1.0f;
    const float length = component(hi_ - lo_, axis_);
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        float start[3];
        start[axis_] = component(hi_, axis_);
        start[u_] = component(lo_, u_) + (float(x) + 0.5f) / pixels_per_unit_;
        start[v_] = component(lo_, v_) + (float(height_ - 1 - y) + 0.5f) / pixels_per_unit_;
        float best = std::numeric_limits<float>::infinity();
        Vec3f normal;
        for (const Body& b : bodies) {
          float t = 0.0f;
          Vec3f n;
          if (traceBody(b, {start[0], start[1], start[2]}, dir, length, &t, &n) && t < best) best = t, normal = n;
        }
        const std::size_t i = std::size_t(y) * width_ + x;
        depth_[i] = best;
        if (std::isfinite(best))
          shade_[i] = (0.3f + 0.7f * std::max(0.0f, dot(normal, light))) * (1.0f - 0.45f * best / length);
      }
  }

  /// Adds a particle at world point `p` (call it every few steps for trails).
  void splat(Vec3f p, Colour c, float weight = 0.15f) {
    const int x = int((component(p, u_) - component(lo_, u_)) * pixels_per_unit_);
    const int y = height_ - 1 - int((component(p, v_) - component(lo_, v_)) * pixels_per_unit_);
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const std::size_t i = std::size_t(y) * width_ + x;
    if (component(hi_, axis_) - component(p, axis_) > depth_[i]) return; // behind a body
    light_[i].r += c.r * weight, light_[i].g += c.g * weight, light_[i].b += c.b * weight;
  }

  /// Writes an RGB PNG: background or body grey, particles blended over it with 1 - exp(-light).
  /// False when the file cannot be written.
  bool write(const std::string& path) const {
    std::vector<std::uint8_t> rgb(depth_.size() * 3);
    for (std::size_t i = 0; i < depth_.size(); ++i) {
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

private:
  // Marches one body along start + t dir, t in [0, t_max]: the first t where its field says distance
  // <= 0, and the normal there. Steps by the sampled distance (sphere tracing), at least a quarter voxel.
  static bool traceBody(const Body& body, Vec3f start, Vec3f dir, float t_max, float* out_t, Vec3f* out_normal) {
    const float h = body.field()->grid().voxel_size * body.scale();
    for (float t = 0.0f; t <= t_max;) {
      const Sample s = body.field()->sample(body.toLocal(start + dir * t));
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

  Vec3f lo_, hi_;
  int axis_, u_, v_;
  int width_, height_;
  float pixels_per_unit_;
  std::vector<float> depth_;  // along the view direction; +inf where no body
  std::vector<float> shade_;  // body shading in [0, 1]
  std::vector<Colour> light_; // accumulated particle light
};

/// The two pictures every sample writes: PREFIX_side.png (looking along a horizontal axis) and
/// PREFIX_top.png (looking down `up`, the world's vertical axis), 640 pixels on the long side, with
/// the bodies drawn and particle trails splatted every other step. An empty prefix draws nothing.
class Trails {
public:
  Trails(const std::string& prefix, Vec3f lo, Vec3f hi, const std::vector<Body>& bodies, Colour colour, int up = 2)
      : prefix_(prefix), colour_(colour), side_(lo, hi, up == 2 ? 1 : 2, prefix.empty() ? 1 : 640),
        top_(lo, hi, up, prefix.empty() ? 1 : 640) {
    if (prefix_.empty()) return;
    side_.drawBodies(bodies);
    top_.drawBodies(bodies);
  }

  /// Splats the particles on even steps.
  void record(int step, const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z) {
    if (prefix_.empty() || step % 2 != 0) return;
    for (std::size_t n = 0; n < x.size(); ++n) {
      side_.splat({x[n], y[n], z[n]}, colour_);
      top_.splat({x[n], y[n], z[n]}, colour_);
    }
  }

  /// Writes both files. False, having said which on stderr, when one cannot be written: the run's
  /// results stand, and exitCode() turns the loss into exit code 2.
  bool write() const {
    if (prefix_.empty()) return true;
    const bool side = writeOrComplain(side_, prefix_ + "_side.png");
    return writeOrComplain(top_, prefix_ + "_top.png") && side;
  }

private:
  static bool writeOrComplain(const Picture& picture, const std::string& path) {
    if (picture.write(path)) return true;
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return false;
  }

  std::string prefix_;
  Colour colour_;
  Picture side_, top_;
};

} // namespace samples
} // namespace dng
