// Analytic signed distance fields for the tests and the benchmarks: exact distance and normal at any
// point, and DenseFields (the std-only writer's input) sampled from them at voxel centres.
#pragma once

#include "dng/format/dense_field.h"
#include "dng/format/vec3.h"

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace dng {
namespace analytic {

/// Exact signed distance (negative inside) and outward unit normal at a point.
struct Exact {
  float distance;
  Vec3f normal;
};
using AnalyticField = std::function<Exact(Vec3f)>;

/// The half-space below the plane dot(n, p) = offset (n is normalized here).
AnalyticField planeField(Vec3f normal, float offset);
/// A solid sphere.
AnalyticField sphereField(Vec3f centre, float radius);
/// A solid axis-aligned box with the given centre and half extents.
AnalyticField boxField(Vec3f centre, Vec3f half_extents);
/// A solid cylinder along z (a "shaft", paper Fig. 7), capped at centre.z +- half_height.
AnalyticField cylinderField(Vec3f centre, float radius, float half_height);

/// A cubic grid of `n` voxels per axis covering [lo, lo + n * voxel_size)^3, band in voxels.
format::GridGeometry cubeGrid(Vec3f lo, float voxel_size, std::uint32_t n, float band_voxels);

/// Samples `field` at every voxel centre of `grid`.
format::DenseField sampleField(const format::GridGeometry& grid, const AnalyticField& field);

/// `count` points uniform in the box [lo, hi), from a fixed seed.
std::vector<Vec3f> randomPoints(Vec3f lo, Vec3f hi, std::size_t count, std::uint32_t seed);

/// Angle between two vectors in degrees (0 when either is zero).
inline float angleDegrees(Vec3f a, Vec3f b) { return float(dng::angleDegrees(a, b)); }

} // namespace analytic
} // namespace dng
