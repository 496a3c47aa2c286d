// Scenes after the paper's figures. Units: metres and seconds; gravity 9.81 m/s^2; 60 steps/s.
#include "figures.h"

#include "picture.h"

#include "dng/format/writer.h"

#include <cmath>

namespace dng {
namespace samples {

namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr float kPi = 3.14159265f;

float uniform(std::mt19937& rng, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }

Body placeBody(const View& field, const Material& material, Vec3f translation = {}) {
  Body body;
  Body::create(&field, material, &body);
  const float m[12] = {1, 0, 0, translation.x, 0, 1, 0, translation.y, 0, 0, 1, translation.z};
  body.setTransform(m);
  return body;
}

// Two views of [lo, hi] with the bodies drawn; particle trails splatted every other step.
// `up` is the world's vertical axis: the side view looks along a horizontal axis, the top view down.
class Trails {
public:
  Trails(const RunOptions& o, Vec3f lo, Vec3f hi, const std::vector<Body>& bodies, Colour colour, int up = 2)
      : enabled_(!o.picture_prefix.empty()), prefix_(o.picture_prefix), colour_(colour),
        side_(lo, hi, up == 2 ? 1 : 2, enabled_ ? o.picture_pixels : 1),
        top_(lo, hi, up, enabled_ ? o.picture_pixels : 1) {
    if (!enabled_) return;
    side_.drawBodies(bodies);
    top_.drawBodies(bodies);
  }
  std::function<void(const Swarm&, int)> recorder() {
    if (!enabled_) return {};
    return [this](const Swarm& swarm, int step) {
      if (step % 2 != 0) return;
      for (std::size_t n = 0; n < swarm.size(); ++n) {
        side_.splat(swarm.position(n), colour_);
        top_.splat(swarm.position(n), colour_);
      }
    };
  }
  void write() const {
    if (!enabled_) return;
    side_.write(prefix_ + "_side.png");
    top_.write(prefix_ + "_top.png");
  }

private:
  bool enabled_;
  std::string prefix_;
  Colour colour_;
  Picture side_, top_;
};

int sized(const RunOptions& o, int full) { return o.particles > 0 ? o.particles : full; }

} // namespace

std::unique_ptr<GeneratedField> generateField(const analytic::AnalyticField& shape, Vec3f lo, Vec3f hi, float voxel,
                                              float band_voxels) {
  format::GridGeometry g;
  g.origin = lo;
  g.voxel_size = voxel;
  g.dims[0] = std::uint32_t(std::ceil((hi.x - lo.x) / voxel));
  g.dims[1] = std::uint32_t(std::ceil((hi.y - lo.y) / voxel));
  g.dims[2] = std::uint32_t(std::ceil((hi.z - lo.z) / voxel));
  g.band = band_voxels * voxel;
  auto out = std::make_unique<GeneratedField>();
  out->bytes = format::encodeBricked(analytic::sampleField(g, shape), {}, "{\"source\":\"analytic\"}").bytes;
  View::open(out->bytes.data(), out->bytes.size(), &out->view);
  return out;
}

FallingResult runFalling(float restitution, float drag, const RunOptions& o) {
  // A table-like box: top face at z = 0, 4 m square.
  const auto field = generateField(analytic::boxField({0, 0, -1}, {2, 2, 1}), {-3, -3, -2.6f}, {3, 3, 1.0f}, 0.1f, 4);
  Material m;
  m.restitution = restitution;
  m.collision_distance = 0.02f;
  m.drag = drag;
  m.contact_distance = 0.1f; // theta = 1 voxel, as the paper's Fig. 3c
  SceneSetup setup;
  setup.bodies = {placeBody(field->view, m)};
  setup.inside = [](Vec3f p) { return analytic::boxField({0, 0, -1}, {2, 2, 1})(p).distance < 0.0f; };
  setup.steps = 180;
  setup.spawn_per_step = sized(o, 2000);
  setup.spawn = [](std::mt19937& rng, Vec3f* p, Vec3f* v) {
    *p = {uniform(rng, -1.5f, 1.5f), uniform(rng, -1.5f, 1.5f), uniform(rng, 2.0f, 2.5f)};
    *v = {uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f), 0.0f};
  };
  Trails trails(o, {-3, -3, -2}, {3, 3, 2.6f}, setup.bodies,
                restitution > 0 ? Colour{1, 0.45f, 0.1f} : Colour{0.1f, 0.5f, 1});
  auto record = trails.recorder();
  std::vector<float> rebound(std::size_t(setup.spawn_per_step), -1.0f);
  Swarm swarm;
  FallingResult r;
  r.stats = runScene(setup, &swarm, [&](const Swarm& s, int step) {
    for (std::size_t n = 0; n < s.size(); ++n) {
      if (s.contact[n])
        rebound[n] = std::max(rebound[n], 0.0f);
      else if (rebound[n] >= 0.0f)
        rebound[n] = std::max(rebound[n], s.pz[n]);
    }
    if (record) record(s, step);
  });
  trails.write();
  double sum = 0;
  std::size_t touched = 0, resting = 0;
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    if (rebound[n] >= 0.0f) sum += rebound[n], ++touched;
    const bool on_top =
        std::fabs(swarm.px[n]) < 2 && std::fabs(swarm.py[n]) < 2 && swarm.pz[n] > -0.05f && swarm.pz[n] < 0.3f;
    resting += on_top && length(swarm.velocity(n)) < 0.2f ? 1 : 0;
  }
  r.mean_rebound_height = touched ? float(sum / double(touched)) : 0.0f;
  r.fraction_resting_on_top = float(resting) / float(swarm.size());
  return r;
}

namespace {

// Fires a stream along `direction` from a disk of `radius` centred on `from`; measures who got past.
StreamResult runStream(const std::vector<Body>& bodies, const analytic::AnalyticField& shape, Vec3f from,
                       Vec3f direction, float speed, float radius, bool gravity, float past, const RunOptions& o,
                       Vec3f view_lo, Vec3f view_hi, Colour colour) {
  SceneSetup setup;
  setup.bodies = bodies;
  setup.inside = [shape](Vec3f p) { return shape(p).distance < 0.0f; }; // the body sits at the origin
  setup.forces.gravity = gravity ? Vec3f{0, 0, -9.81f} : Vec3f{};
  // Without gravity the stream is carried by the air moving with it (as smoke in a draught), so
  // particles slowed by the obstacle pick up speed again downstream.
  if (!gravity) {
    setup.forces.air_drag = 2.0f;
    setup.forces.wind = direction * speed;
  }
  setup.steps = 150;
  setup.spawn_steps = 60;
  setup.spawn_per_step = std::max(1, sized(o, 6000) / 60);
  const Vec3f u = std::fabs(direction.z) > 0.9f ? Vec3f{1, 0, 0} : normalizeOrZero(cross(direction, {0, 0, 1}));
  const Vec3f w = cross(direction, u);
  std::vector<float> start_offsets; // each particle's distance from the stream's axis at spawn
  setup.spawn = [&](std::mt19937& rng, Vec3f* p, Vec3f* v) {
    const float r = radius * std::sqrt(uniform(rng, 0, 1)), a = uniform(rng, 0, 2 * kPi);
    *p = from + u * (r * std::cos(a)) + w * (r * std::sin(a));
    *v = direction * speed;
    start_offsets.push_back(r);
  };
  Trails trails(o, view_lo, view_hi, bodies, colour);
  Swarm swarm;
  StreamResult result;
  result.stats = runScene(setup, &swarm, trails.recorder());
  trails.write();
  // Of the particles that started aimed at the obstacle (within half the disk), who got past it?
  std::size_t aimed = 0, past_count = 0;
  double offset_sum = 0;
  for (std::size_t n = 0; n < swarm.size(); ++n) {
    if (start_offsets[n] > 0.5f * radius) continue;
    ++aimed;
    const Vec3f p = swarm.position(n) - from;
    const float along = dot(p, direction);
    if (along > past) {
      ++past_count;
      offset_sum += length(p - direction * along);
    }
  }
  result.fraction_downstream = aimed ? float(past_count) / float(aimed) : 0.0f;
  result.mean_downstream_offset = past_count ? float(offset_sum / double(past_count)) : 0.0f;
  return result;
}

Material flowMaterial(float rho_in, float rho_out, float flow_distance) {
  Material m;
  m.restitution = 0.0f;
  m.collision_distance = 0.02f;
  m.flow_in = rho_in;
  m.flow_out = rho_out;
  m.flow_distance = flow_distance;
  return m;
}

} // namespace

StreamResult runSphereStream(bool from_above, const RunOptions& o) {
  const analytic::AnalyticField shape = analytic::sphereField({0, 0, 0}, 1.0f);
  static const auto field = generateField(shape, {-1.4f, -1.4f, -1.4f}, {1.4f, 1.4f, 1.4f}, 0.05f, 4);
  const std::vector<Body> bodies = {placeBody(field->view, flowMaterial(12.0f, 3.0f, 0.2f))};
  if (from_above)
    return runStream(bodies, shape, {0, 0, 2.5f}, {0, 0, -1}, 2.0f, 0.7f, true, 3.5f, o, {-2.5f, -2.5f, -2.5f},
                     {2.5f, 2.5f, 2.5f}, {0.2f, 0.55f, 1.0f});
  return runStream(bodies, shape, {-2.5f, 0, 0}, {1, 0, 0}, 3.0f, 0.7f, false, 3.5f, o, {-2.5f, -2.5f, -2.5f},
                   {2.5f, 2.5f, 2.5f}, {0.2f, 0.55f, 1.0f});
}

StreamResult runShaftStream(float rho_in, float rho_out, float flow_distance, const RunOptions& o) {
  const analytic::AnalyticField shape = analytic::cylinderField({0, 0, 0}, 0.4f, 1.0f);
  static const auto field = generateField(shape, {-0.8f, -0.8f, -1.4f}, {0.8f, 0.8f, 1.4f}, 0.04f, 5);
  const std::vector<Body> bodies = {placeBody(field->view, flowMaterial(rho_in, rho_out, flow_distance))};
  return runStream(bodies, shape, {2.0f, 0, 0}, {-1, 0, 0}, 2.5f, 0.5f, false, 2.8f, o, {-2.2f, -1.6f, -1.2f},
                   {2.2f, 1.6f, 1.2f}, {1.0f, 0.5f, 0.15f});
}

ExplosionResult runExplosion(const RunOptions& o) {
  static const auto ground = generateField(analytic::boxField({0, 0, -0.25f}, {6, 6, 0.25f}), {-6.4f, -6.4f, -0.9f},
                                           {6.4f, 6.4f, 0.6f}, 0.1f, 4);
  static const auto building = generateField(analytic::boxField({0, 0, 1.0f}, {0.6f, 0.6f, 1.0f}),
                                             {-1.0f, -1.0f, -0.4f}, {1.0f, 1.0f, 2.4f}, 0.05f, 5);
  Material m = flowMaterial(8.0f, 2.0f, 0.15f);
  m.restitution = 0.2f;
  m.swept = true; // the blast throws particles far faster than the fields' reach per step
  SceneSetup setup;
  setup.bodies.push_back(placeBody(ground->view, m));
  std::vector<Vec3f> sites;
  for (int i = 0; i < 6; ++i) { // one field, six buildings
    const float a = 2 * kPi * float(i) / 6.0f + 0.3f;
    sites.push_back({2.4f * std::cos(a), 2.4f * std::sin(a), 0.0f});
    setup.bodies.push_back(placeBody(building->view, m, sites.back()));
  }
  setup.inside = [sites](Vec3f p) {
    bool inside = analytic::boxField({0, 0, -0.25f}, {6, 6, 0.25f})(p).distance < 0.0f;
    for (const Vec3f& site : sites)
      inside = inside || analytic::boxField(site + Vec3f{0, 0, 1.0f}, {0.6f, 0.6f, 1.0f})(p).distance < 0.0f;
    return inside;
  };
  setup.forces.air_drag = 1.5f;
  setup.forces.explosion_strength = 150.0f;
  setup.forces.explosion_centre = {0, 0, 0.3f};
  setup.forces.explosion_radius = 0.6f;
  setup.forces.explosion_seconds = 0.25f;
  setup.steps = 150;
  setup.spawn_per_step = sized(o, 6000);
  setup.spawn = [](std::mt19937& rng, Vec3f* p, Vec3f* v) {
    *p = {uniform(rng, -0.3f, 0.3f), uniform(rng, -0.3f, 0.3f), uniform(rng, 0.1f, 0.6f)};
    *v = {uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, 0, 3)};
  };
  Trails trails(o, {-5.5f, -5.5f, -0.5f}, {5.5f, 5.5f, 3.0f}, setup.bodies, {1.0f, 0.4f, 0.1f});
  Swarm swarm;
  ExplosionResult r;
  r.stats = runScene(setup, &swarm, trails.recorder());
  trails.write();
  std::size_t beyond = 0;
  for (std::size_t n = 0; n < swarm.size(); ++n)
    beyond += std::hypot(swarm.px[n], swarm.py[n]) > 3.1f ? 1 : 0;
  r.fraction_beyond_buildings = float(beyond) / float(swarm.size());
  return r;
}

SheetResult runSheet(const View& field, const RunOptions& o) {
  Material m;
  m.restitution = 0.3f;
  m.collision_distance = 0.2f * field.grid().voxel_size;
  SceneSetup setup;
  setup.bodies = {placeBody(field, m)};
  setup.forces.gravity = {};
  setup.steps = 60;
  setup.spawn_per_step = sized(o, 4000);
  const GridInfo& g = field.grid();
  const Vec3f size = Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  const float reach = field.guaranteedReach(), speed = 0.8f * reach / kDt;
  // Particles start in the band on either side of the sheet, each facing the surface plane it sees
  // (closest point q, normal n); it has crossed if it gets behind that plane near where it started.
  struct Start {
    Vec3f closest, normal;
  };
  std::vector<Start> starts;
  // Aim down the gradient of the distance (trilinear: independent of the stored normals, so a
  // one-sided field is put to the test from both sides).
  auto away = [&](Vec3f q) {
    const float e = 0.5f * g.voxel_size;
    auto d = [&](Vec3f x) { return field.sample(x, Interpolation::kTrilinear).distance; };
    return normalizeOrZero({d(q + Vec3f{e, 0, 0}) - d(q - Vec3f{e, 0, 0}),
                            d(q + Vec3f{0, e, 0}) - d(q - Vec3f{0, e, 0}),
                            d(q + Vec3f{0, 0, e}) - d(q - Vec3f{0, 0, e})});
  };
  // Only over the sheet's interior: there the distance stays the same when moving 3 voxels along
  // the sheet. Near a rim it grows; there particles may go around the edge, and the potential
  // method's normals turn sideways (a limitation of method 2 that the sample does not hide:
  // docs/SAMPLES.md).
  auto overInterior = [&](Vec3f q, Vec3f n, float d) {
    const Vec3f t1 = normalizeOrZero(cross(n, std::fabs(n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    const Vec3f t2 = cross(n, t1);
    for (Vec3f t : {t1, t1 * -1.0f, t2, t2 * -1.0f}) {
      const Sample s = field.sample(q + t * (3.0f * g.voxel_size), Interpolation::kTrilinear);
      if (s.status != SampleStatus::kInBand || std::fabs(s.distance - d) > 0.1f * g.voxel_size) return false;
    }
    return true;
  };
  setup.spawn = [&](std::mt19937& rng, Vec3f* p, Vec3f* v) {
    for (;;) {
      const Vec3f q = g.origin + Vec3f{uniform(rng, 0, size.x), uniform(rng, 0, size.y), uniform(rng, 0, size.z)};
      const Sample s = field.sample(q, Interpolation::kTrilinear);
      if (s.status != SampleStatus::kInBand || s.distance < 0.4f * reach || s.distance > 0.9f * reach) continue;
      const Vec3f n = away(q);
      if (dot(n, n) == 0.0f || !overInterior(q, n, s.distance)) continue;
      *p = q;
      *v = n * -speed;
      starts.push_back({q - n * s.distance, n});
      return;
    }
  };
  Trails trails(o, g.origin, g.origin + size, setup.bodies, {0.3f, 0.8f, 0.3f});
  const auto record = trails.recorder();
  std::vector<std::uint8_t> crossed;
  Swarm swarm;
  SheetResult r;
  r.stats = runScene(setup, &swarm, [&](const Swarm& sw, int step) {
    // Checked every step near the start: a particle that got through keeps flying away.
    crossed.resize(sw.size(), 0);
    for (std::size_t n = 0; n < sw.size(); ++n) {
      const Vec3f from_plane = sw.position(n) - starts[n].closest;
      if (length(from_plane) < 2.0f * g.band && dot(from_plane, starts[n].normal) < 0.0f) crossed[n] = 1;
    }
    if (record) record(sw, step);
  });
  trails.write();
  for (std::uint8_t c : crossed)
    r.crossed += c;
  return r;
}

SceneStats runDemo(const View& field, int up, const RunOptions& o) {
  const GridInfo& g = field.grid();
  const Vec3f size = Vec3f{float(g.dims[0]), float(g.dims[1]), float(g.dims[2])} * g.voxel_size;
  const Vec3f lo = g.origin, hi = g.origin + size;
  Material m;
  m.restitution = 0.45f;
  m.collision_distance = 0.3f * g.voxel_size;
  m.drag = 1.0f;
  m.contact_distance = g.voxel_size;
  m.flow_in = 3.0f;
  m.flow_out = 1.0f;
  m.flow_distance = 2.0f * g.voxel_size;
  m.swept = true; // falling particles may outrun the band: trace their steps
  SceneSetup setup;
  setup.bodies = {placeBody(field, m)};
  const float height = component(size, up);
  Vec3f down;
  component(down, up) = -9.81f * height / 2.0f; // a ~1 unit mesh: scale gravity to it
  setup.forces.gravity = down;
  setup.steps = 240;
  setup.spawn_steps = 120;
  setup.spawn_per_step = std::max(1, sized(o, 24000) / 120);
  setup.spawn = [=](std::mt19937& rng, Vec3f* p, Vec3f* v) {
    float c[3];
    const float l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    for (int a = 0; a < 3; ++a)
      c[a] = uniform(rng, l[a] + 0.2f * (h[a] - l[a]), h[a] - 0.2f * (h[a] - l[a]));
    c[up] = uniform(rng, h[up] - 0.08f * height, h[up] - 0.01f * height); // a thin slab: no banding
    *p = {c[0], c[1], c[2]};
    *v = {0, 0, 0};
  };
  Trails trails(o, lo, hi, setup.bodies, {1.0f, 0.55f, 0.15f}, up);
  Swarm swarm;
  const SceneStats stats = runScene(setup, &swarm, trails.recorder());
  trails.write();
  if (o.final_positions != nullptr)
    for (std::size_t n = 0; n < swarm.size(); ++n)
      o.final_positions->push_back(swarm.position(n));
  return stats;
}

} // namespace samples
} // namespace dng
