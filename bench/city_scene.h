// The many-bodies benchmarks' scene (paper Fig. 8): a city of 1,000 box buildings sharing ONE box
// field, each placed with its own scale and turn on a lattice, on a ground slab (a second field), and
// 100,000 raindrops falling among them. Built once per process, from analytic fields.
//
// Also the same raindrops folded onto one building: each drop carried from its own building's frame
// into building 0's, so that against building 0 alone it follows the same local path as against its
// own building in the city (speeds scale with the building, so the walk takes the same samples).
#pragma once

#include "analytic_fields.h"
#include "dng/body.h"
#include "dng/format/writer.h"
#include "dng/particles.h"
#include "dng/view.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace dng {
namespace bench {

constexpr int kLatticeX = 40, kLatticeY = 25; // 1,000 buildings
// World units between lattice points: wide enough that no two buildings' grids overlap (a grid reaches
// 1.625 * 4 * sqrt(2) = 9.2 from its building's axis at most), so a drop is in at most one building's box
// and the folded drops below do the same field work against one building as in the city.
constexpr float kSpacing = 20.0f;
constexpr std::size_t kRaindrops = 100000;
constexpr float kCityDt = 1.0f / 60.0f;

struct Raindrops {
  std::vector<float> px, py, pz, vx, vy, vz;
  ParticleSpan span(std::size_t begin = 0, std::size_t end = SIZE_MAX) {
    end = end < px.size() ? end : px.size();
    ParticleSpan s;
    s.position_x = px.data() + begin, s.position_y = py.data() + begin, s.position_z = pz.data() + begin;
    s.velocity_x = vx.data() + begin, s.velocity_y = vy.data() + begin, s.velocity_z = vz.data() + begin;
    s.count = end - begin;
    return s;
  }
};

struct City {
  std::vector<std::uint8_t> building_bytes, ground_bytes;
  View building, ground;
  Body ground_body;
  std::vector<Body> buildings; // ground first, then the buildings: 1,001 bodies
  Raindrops rain;
  Raindrops folded; // rain carried into building 0's neighbourhood (body 1 of `buildings`)
  // The same two, ordered by lattice cell (row, then column), as an engine that keeps its particles
  // in spatial order has them.
  Raindrops rain_sorted, folded_sorted;
};

namespace detail {

// A unit building in its own frame: a box 2 x 2 x 4 standing on z = 0, in voxels of 1/8, band 3
// voxels plus the half-diagonal guard; the grid reaches a voxel beyond the band (as dngbake's do).
inline format::GridGeometry buildingGrid() {
  format::GridGeometry g;
  g.voxel_size = 0.125f;
  g.band = 3.8661f * g.voxel_size;
  g.origin = {-1.625f, -1.625f, -0.625f};
  g.dims[0] = g.dims[1] = 26;
  g.dims[2] = 42;
  return g;
}

// The ground: a slab 8 deep whose top is z = 0, under the whole lattice and 20 units beyond, in voxels
// of 2 world units.
inline format::GridGeometry groundGrid() {
  format::GridGeometry g;
  g.voxel_size = 2.0f;
  g.band = 3.8661f * g.voxel_size;
  g.origin = {-20.0f - 0.5f * kSpacing, -20.0f - 0.5f * kSpacing, -16.0f};
  g.dims[0] = std::uint32_t((kLatticeX * kSpacing + 40.0f) / g.voxel_size);
  g.dims[1] = std::uint32_t((kLatticeY * kSpacing + 40.0f) / g.voxel_size);
  g.dims[2] = 12;
  return g;
}

inline Raindrops reordered(const Raindrops& in, const std::vector<std::size_t>& order) {
  Raindrops out;
  for (std::size_t n : order) {
    out.px.push_back(in.px[n]), out.py.push_back(in.py[n]), out.pz.push_back(in.pz[n]);
    out.vx.push_back(in.vx[n]), out.vy.push_back(in.vy[n]), out.vz.push_back(in.vz[n]);
  }
  return out;
}

inline View openView(const std::vector<std::uint8_t>& bytes) {
  View view;
  View::open(bytes.data(), bytes.size(), &view);
  return view;
}

} // namespace detail

/// Building b (0-based) stands at lattice point (b % kLatticeX, b / kLatticeX) with scale 2..4 (4 to 8
/// wide, 8 to 16 tall) and a turn about z; the ground is body 0 of City::buildings.
inline const City& city() {
  static const City* scene = [] {
    auto* c = new City;
    const format::GridGeometry bg = detail::buildingGrid(), gg = detail::groundGrid();
    c->building_bytes =
        format::encodeBricked(analytic::sampleField(bg, analytic::boxField({0, 0, 2}, {1, 1, 2})), {}, "").bytes;
    const Vec3f ground_centre{0.5f * (kLatticeX - 1) * kSpacing, 0.5f * (kLatticeY - 1) * kSpacing, -4.0f};
    c->ground_bytes =
        format::encodeBricked(analytic::sampleField(gg, analytic::boxField(ground_centre, {1e4f, 1e4f, 4.0f})), {}, "")
            .bytes;
    c->building = detail::openView(c->building_bytes);
    c->ground = detail::openView(c->ground_bytes);
    Material material;
    material.restitution = 0.3f;
    material.collision_distance = 0.05f;
    material.drag = 4.0f, material.contact_distance = 0.2f; // rain runs down walls
    Body::create(&c->ground, material, &c->ground_body);
    c->buildings.push_back(c->ground_body);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    struct Placed {
      Vec3f at;
      float scale, turn;
    };
    std::vector<Placed> placed;
    std::vector<int> drop_cells;
    for (int b = 0; b < kLatticeX * kLatticeY; ++b) {
      const Placed p{{float(b % kLatticeX) * kSpacing, float(b / kLatticeX) * kSpacing, 0.0f},
                     2.0f + 2.0f * unit(rng),
                     3.14159265f * unit(rng)};
      const float q[4] = {std::cos(0.5f * p.turn), 0.0f, 0.0f, std::sin(0.5f * p.turn)};
      Body body;
      Body::create(&c->building, material, &body);
      body.setTransform(p.at, q, p.scale);
      c->buildings.push_back(body);
      placed.push_back(p);
    }
    // Raindrops anywhere over the city up to 20 units high, not inside a building, falling at about
    // 12 units/s with a little wind.
    while (c->rain.px.size() < kRaindrops) {
      const Vec3f p{(unit(rng) * kLatticeX - 0.5f) * kSpacing, (unit(rng) * kLatticeY - 0.5f) * kSpacing,
                    0.5f + 19.5f * unit(rng)};
      const int column = std::min(int(std::lround(p.x / kSpacing)), kLatticeX - 1);
      const int row = std::min(int(std::lround(p.y / kSpacing)), kLatticeY - 1);
      const int cell = std::max(row, 0) * kLatticeX + std::max(column, 0);
      // Buildings never reach into a neighbour's cell: only the drop's own can hold it.
      const Vec3f local = c->buildings[std::size_t(cell) + 1].toLocal(p);
      const float margin = 0.3f / placed[std::size_t(cell)].scale;
      if (std::fabs(local.x) < 1.0f + margin && std::fabs(local.y) < 1.0f + margin && local.z < 4.0f + margin) continue;
      const Vec3f v{2.0f + 2.0f * unit(rng) - 1.0f, 1.0f + 2.0f * unit(rng) - 1.0f, -12.0f + 4.0f * unit(rng) - 2.0f};
      c->rain.px.push_back(p.x), c->rain.py.push_back(p.y), c->rain.pz.push_back(p.z);
      c->rain.vx.push_back(v.x), c->rain.vy.push_back(v.y), c->rain.vz.push_back(v.z);
      // Folded: building 0's world from the drop's own building's local frame.
      const Body& own = c->buildings[std::size_t(cell) + 1];
      const Body& first = c->buildings[1];
      const Vec3f fp = first.toWorld(own.toLocal(p)), fv = first.toWorld(own.toLocal(p + v)) - fp;
      c->folded.px.push_back(fp.x), c->folded.py.push_back(fp.y), c->folded.pz.push_back(fp.z);
      c->folded.vx.push_back(fv.x), c->folded.vy.push_back(fv.y), c->folded.vz.push_back(fv.z);
      drop_cells.push_back(cell);
    }
    std::vector<std::size_t> order(drop_cells.size());
    for (std::size_t n = 0; n < order.size(); ++n)
      order[n] = n;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return drop_cells[a] < drop_cells[b]; });
    c->rain_sorted = detail::reordered(c->rain, order);
    c->folded_sorted = detail::reordered(c->folded, order);
    return c;
  }();
  return *scene;
}

} // namespace bench
} // namespace dng
