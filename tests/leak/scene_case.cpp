#include "scene_case.h"

#include "case_setup.h"
#include "dng/forces.h"
#include "swarm_judge.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>

namespace dng {
namespace leak {

namespace {

// Particles resting on a floor start this far above it, in its voxels (as the single-body resting cases).
constexpr float kRestingHeight = 0.15f;
// Gravity's gain over a 120-step run, in design speeds: the single-body cases' figures.
constexpr float kRestingGain = 0.5f, kThrownGain = 0.1f;

Vec3f downward(float gain, float design_speed) { return {0.0f, 0.0f, -gain * design_speed / (120.0f * kDt)}; }

// Outside every body (at its pose in `bodies`) and at least 0.1 of its voxel from its surface.
bool clearOfBodies(const SceneSpec& spec, const std::vector<Body>& bodies, Vec3f p) {
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Subject& s = *spec.bodies[b].subject;
    const Vec3f local = bodies[b].toLocal(p);
    if (s.mesh.closed && s.reference.inside(local)) return false;
    const reference::Closest c = s.reference.closest(local, 0.1f * s.voxel);
    if (c.found && c.distance < 0.1f * s.voxel) return false;
  }
  return true;
}

// The scene's particles; its spawn box must have room outside the bodies.
testing::Swarm spawnSwarm(const SceneSpec& spec, const std::vector<Body>& bodies) {
  std::mt19937 rng(spec.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  const Vec3f lo = spec.spawn_lo, extent = spec.spawn_hi - spec.spawn_lo;
  testing::Swarm swarm;
  while (swarm.size() < spec.particles) {
    const Vec3f p = lo + Vec3f{extent.x * unit(rng), extent.y * unit(rng), extent.z * unit(rng)};
    if (!clearOfBodies(spec, bodies, p)) continue;
    const Vec3f direction = normalizeOrZero({gauss(rng), gauss(rng), gauss(rng)});
    swarm.add(p, direction * (spec.spawn_speed * (0.2f + 0.8f * unit(rng))));
  }
  return swarm;
}

// A closed box centred on the origin (its half extents) and the resolution it is baked at.
struct BoxSpec {
  const char* name;
  Vec3f half;
  int resolution;
};

// Bakes `boxes` in `mode`, in order, onto *out. False (with *out_error) at the first that fails.
bool bakeBoxes(std::initializer_list<BoxSpec> boxes, baker::NormalMode mode, const std::string& folder,
               std::string* out_error, std::vector<std::unique_ptr<Subject>>* out) {
  for (const BoxSpec& box : boxes) {
    out->push_back(
        bakeSubject({box.name, testing::boxMesh({0, 0, 0}, box.half), true}, mode, folder, out_error, box.resolution));
    if (!out->back()) return false;
  }
  return true;
}

} // namespace

float designSpeed(const std::vector<SceneBody>& bodies) {
  float slowest = std::numeric_limits<float>::infinity();
  for (const SceneBody& b : bodies)
    slowest = std::min(slowest, b.subject->reach / kDt);
  return slowest;
}

CaseResult runScene(const SceneSpec& spec) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t count = spec.bodies.size();
  CaseSpec materials;
  materials.responses = spec.responses;
  materials.swept = spec.swept;
  std::vector<CaseSetup> setups;
  std::vector<Body> before(count);
  for (std::size_t b = 0; b < count; ++b) {
    const SceneBody& body = spec.bodies[b];
    CaseSetup setup = makeSetup(*body.subject, materials);
    setup.position = body.position, setup.linear = body.linear, setup.angular = body.angular;
    (void)Body::create(&body.subject->file.view(), setup.material, &before[b]);
    placeBody(setup, 0.0f, &before[b]);
    setups.push_back(setup);
  }
  std::vector<Body> after = before;
  testing::Swarm swarm = spawnSwarm(spec, before);
  std::vector<std::unique_ptr<SwarmJudge>> judges;
  for (std::size_t b = 0; b < count; ++b)
    judges.push_back(std::make_unique<SwarmJudge>(*spec.bodies[b].subject, before[b], swarm));

  CaseResult result;
  for (int k = 0; k < spec.steps; ++k) {
    for (std::size_t b = 0; b < count; ++b) {
      placeBody(setups[b], float(k) * kDt, &before[b]);
      placeBody(setups[b], float(k + 1) * kDt, &after[b]);
      result.fast_steps += countFast(*spec.bodies[b].subject, before[b], setups[b].speed_limit, swarm);
    }
    (void)applyGravity(swarm.span(), spec.gravity, kDt);
    result.contacts += stepInParallel(before.data(), count, kDt, &swarm);
    for (std::size_t b = 0; b < count; ++b)
      judges[b]->judgeStep(after[b], swarm);
  }
  std::vector<float> depths;
  for (const auto& judge : judges)
    judge->addTo(&result, &depths);
  setMedianDepth(&depths, &result);
  result.particle_steps = std::uint64_t(swarm.size()) * std::uint64_t(spec.steps);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

namespace {

// Crates 8 units wide (voxels of 0.4 unit) on a ground 120 x 26 x 4 (voxels of 1) whose top is at z = 2. The crates
// rest flush on the ground, so the particles resting on it lie in their way. Each moves for a number of steps at a
// fraction of the design speed v, and its start follows from where it must end.
std::vector<SceneSpec> crateScenes(const Subject* ground, const Subject* crate, const Subject* wall) {
  std::vector<SceneSpec> scenes;
  const float top = 2.0f, on_ground = top + 4.0f, rest = top + kRestingHeight;
  const float v = designSpeed({{ground}, {crate}, {wall}});
  const Vec3f resting = downward(kRestingGain, v);
  const auto travel = [&](float fraction, int steps) { return fraction * v * float(steps) * kDt; };

  SceneSpec slide("a crate slides along the ground into resting particles (0.5 design speed)");
  const float slid = travel(0.5f, slide.steps);
  slide.bodies = {{ground}, {crate, {-40, 0, on_ground}, {0.5f * v, 0, 0}}};
  slide.spawn_lo = {-34, -3.5f, rest}, slide.spawn_hi = {-36 + slid, 3.5f, rest};
  slide.gravity = resting;
  scenes.push_back(slide);

  // The wall stands on the ground with its face at x = 40; the crate's front ends at x = 39.
  SceneSpec into_wall("a crate pushes resting particles into a wall, stopping 1 unit short (0.4 design speed)");
  const float start = 35.0f - travel(0.4f, into_wall.steps);
  into_wall.bodies = {{ground}, {wall, {41, 0, top + 6}}, {crate, {start, 0, on_ground}, {0.4f * v, 0, 0}}};
  into_wall.spawn_lo = {start + 6, -3.5f, rest}, into_wall.spawn_hi = {39.5f, 3.5f, rest};
  into_wall.gravity = resting;
  scenes.push_back(into_wall);

  // Their fronts end 1 unit apart, at x = -0.5 and 0.5.
  SceneSpec close("two crates close in on resting particles, stopping 1 unit apart (0.4 design speed each)");
  close.steps = 45;
  const float from = 4.5f + travel(0.4f, close.steps);
  close.bodies = {
      {ground}, {crate, {-from, 0, on_ground}, {0.4f * v, 0, 0}}, {crate, {from, 0, on_ground}, {-0.4f * v, 0, 0}}};
  close.spawn_lo = {6 - from, -3.5f, rest}, close.spawn_hi = {from - 6, 3.5f, rest};
  close.gravity = resting;
  scenes.push_back(close);

  // Both move along +x; the faster one behind catches up until its front is 1 unit short of the other's
  // back: particles it pushes meet a body that is moving too.
  SceneSpec catch_up("a crate pushes resting particles into a slower crate ahead, stopping 1 unit behind it "
                     "(0.6 and 0.2 design speed)");
  const float gap = 1.0f + travel(0.4f, catch_up.steps);
  catch_up.bodies = {
      {ground}, {crate, {-8 - gap, 0, on_ground}, {0.6f * v, 0, 0}}, {crate, {0, 0, on_ground}, {0.2f * v, 0, 0}}};
  catch_up.spawn_lo = {-2 - gap, -3.5f, rest}, catch_up.spawn_hi = {-4.5f, 3.5f, rest};
  catch_up.gravity = resting;
  scenes.push_back(catch_up);

  // No ground: the crates fly past each other with a 1-unit gap between their sides at y = +-0.5.
  SceneSpec pass("two crates pass each other 1 unit apart through thrown particles (0.5 design speed each)");
  const float half_way = 0.5f * travel(0.5f, pass.steps);
  pass.bodies = {{crate, {-half_way, -4.5f, 0}, {0.5f * v, 0, 0}}, {crate, {half_way, 4.5f, 0}, {-0.5f * v, 0, 0}}};
  pass.spawn_lo = {-0.5f * half_way, -0.4f, -4}, pass.spawn_hi = {0.5f * half_way, 0.4f, 4};
  pass.spawn_speed = 0.3f * v;
  pass.gravity = downward(kThrownGain, v);
  scenes.push_back(pass);

  SceneSpec down("a crate comes down onto resting particles, stopping 1 unit above the ground (0.4 design speed)");
  down.steps = 30;
  down.bodies = {{ground}, {crate, {0, 0, on_ground + 1 + travel(0.4f, down.steps)}, {0, 0, -0.4f * v}}};
  down.spawn_lo = {-3.5f, -3.5f, rest}, down.spawn_hi = {3.5f, 3.5f, rest};
  down.gravity = resting;
  scenes.push_back(down);

  // Rolling about y: its edges (5.66 units from its centre) sweep the ground 0.05 unit above it, under
  // the particles resting there, at up to half the design speed (a quarter from the turn, a quarter
  // from the roll).
  SceneSpec tumble("a crate tumbles along the ground, its edges sweeping 0.05 unit above it under resting particles");
  const float edge = std::sqrt(32.0f);
  tumble.bodies = {{ground}, {crate, {-40, 0, top + edge + 0.05f}, {0.25f * v, 0, 0}, {0, 0.25f * v / edge, 0}}};
  tumble.spawn_lo = {-40 + edge, -3.5f, rest}, tumble.spawn_hi = {-40 + edge + travel(0.25f, tumble.steps), 3.5f, rest};
  tumble.gravity = resting;
  scenes.push_back(tumble);
  return scenes;
}

// A mesh (its voxel h) with a ground box 240 x 120 x 20 voxels of its own.
std::vector<SceneSpec> meshScenes(const Subject& mesh, const Subject* ground) {
  std::vector<SceneSpec> scenes;
  const float h = mesh.voxel;
  Vec3f lo, hi;
  meshBounds(mesh.mesh, &lo, &hi);
  const float v = designSpeed({{ground}, {&mesh}});

  // Sunk 3 voxels into the ground: particles are only where the mesh meets the ground's top.
  const float top = lo.z + 3.0f * h;
  float y0 = hi.y, y1 = lo.y;
  for (const Vec3f& p : mesh.mesh.mesh.vertices)
    if (p.z < top + h) y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  SceneSpec slide(mesh.mesh.name + ", sunk 3 voxels into a ground, slides into resting particles (0.5 design speed)");
  slide.bodies = {{ground, {0, 0, top - 10 * h}}, {&mesh, {0, 0, 0}, {0.5f * v, 0, 0}}};
  slide.spawn_lo = {hi.x + h, y0, top + 0.5f * h}, slide.spawn_hi = {hi.x + 40 * h, y1, top + 0.5f * h};
  slide.gravity = downward(0.2f, v); // lighter: the particles lie on the ground longer as the mesh arrives
  slide.steps = 30;
  scenes.push_back(slide);

  // Spinning about the vertical through its centre, its farthest point at half the design speed.
  float radius = 0.0f;
  for (const Vec3f& p : mesh.mesh.mesh.vertices)
    radius = std::max(radius, std::hypot(p.x, p.y));
  SceneSpec spin(mesh.mesh.name + " spins 1 voxel above a ground through thrown particles");
  spin.bodies = {{ground, {0, 0, lo.z - 11 * h}}, {&mesh, {0, 0, 0}, {}, {0, 0, 0.5f * v / radius}}};
  const Vec3f pad{mesh.reach, mesh.reach, mesh.reach};
  spin.spawn_lo = lo - pad, spin.spawn_hi = hi + pad;
  spin.spawn_speed = 0.3f * v;
  spin.gravity = downward(kThrownGain, v);
  scenes.push_back(spin);
  return scenes;
}

// Random scenes (SceneSet::random): the movers' shapes, and the ground they move over.
struct RandomScenes {
  const Subject* ground;
  std::vector<const Subject*> shapes;
  float speed; ///< the movers' largest speed, design speeds
  std::mt19937 rng;

  float unit() { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng); }

  // A mover that slides along the ground or spins just above it, its path at least 1 unit from the
  // paths of `placed` (spheres about their centres, of `radii`). False when it would not fit.
  bool place(const Subject* shape, float v, int steps, std::vector<SceneBody>* placed, std::vector<float>* radii) {
    Vec3f lo, hi;
    meshBounds(shape->mesh, &lo, &hi);
    const float radius = length(hi);
    const bool spin = unit() < 0.5f;
    const float clearance = unit() < 0.5f ? 0.05f : 1.0f;
    const float linear = speed * v * unit(), heading = 6.2831853f * unit();
    const Vec3f velocity{linear * std::cos(heading), linear * std::sin(heading), 0.0f};
    Vec3f angular;
    if (spin) // the farthest point's speed from the turn and the slide together stays within `speed`
      angular =
          normalizeOrZero({unit() - 0.5f, unit() - 0.5f, unit() - 0.5f}) * ((speed * v - linear) * unit() / radius);
    const Vec3f at{-30.0f + 60.0f * unit(), -30.0f + 60.0f * unit(), (spin ? radius : hi.z) + clearance};
    const Vec3f end = at + velocity * (float(steps) * kDt);
    if (std::fabs(end.x) > 50.0f || std::fabs(end.y) > 50.0f) return false; // stays over the ground
    for (std::size_t j = 0; j < placed->size(); ++j)
      for (int k = 0; k <= steps; ++k) {
        const float t = float(k) * kDt;
        const Vec3f other = (*placed)[j].position + (*placed)[j].linear * t;
        if (length(at + velocity * t - other) < radius + (*radii)[j] + 1.0f) return false;
      }
    placed->push_back({shape, at, velocity, angular});
    radii->push_back(radius);
    return true;
  }

  SceneSpec next(int index) {
    SceneSpec scene("random scene " + std::to_string(index));
    std::vector<const Subject*> chosen;
    const int movers = 2 + int(unit() * 3.0f) % 3;
    for (int i = 0; i < movers; ++i)
      chosen.push_back(shapes[std::size_t(unit() * float(shapes.size())) % shapes.size()]);
    std::vector<SceneBody> bodies{{ground, {0, 0, -2}}};
    for (const Subject* shape : chosen)
      bodies.push_back({shape});
    const float v = designSpeed(bodies);
    bodies.erase(bodies.begin() + 1, bodies.end());
    std::vector<SceneBody> placed;
    std::vector<float> radii;
    for (const Subject* shape : chosen)
      for (int tries = 0; tries < 100 && !place(shape, v, scene.steps, &placed, &radii); ++tries) {
      }
    bodies.insert(bodies.end(), placed.begin(), placed.end());
    scene.bodies = bodies;
    const bool resting = unit() < 0.5f;
    scene.spawn_lo = {-40, -40, resting ? kRestingHeight : 0.2f};
    scene.spawn_hi = {40, 40, resting ? kRestingHeight : 12.0f};
    scene.spawn_speed = resting ? 0.0f : 0.3f * v;
    scene.gravity = downward(resting ? kRestingGain : kThrownGain, v);
    const Responses materials[] = {Responses::kImpact, Responses::kImpactDragFlow, Responses::kSpring};
    scene.responses = materials[std::size_t(unit() * 3.0f) % 3];
    return scene;
  }
};

} // namespace

std::unique_ptr<SceneSet> SceneSet::boxes(baker::NormalMode mode, const std::string& folder, std::string* out_error) {
  std::unique_ptr<SceneSet> set(new SceneSet);
  // Voxels of one unit for the ground and the wall (their longest sides plus the band's padding), 0.4
  // for the crates, which set the scenes' design speed.
  if (!bakeBoxes({{"scene ground", {60, 13, 2}, 132}, {"scene crate", {4, 4, 4}, 32}, {"scene wall", {1, 13, 6}, 38}},
                 mode, folder, out_error, &set->bodies_))
    return nullptr;
  set->scenes_ = crateScenes(set->bodies_[0].get(), set->bodies_[1].get(), set->bodies_[2].get());
  return set;
}

std::unique_ptr<SceneSet> SceneSet::aroundMesh(const Subject& mesh, const std::string& folder, std::string* out_error) {
  std::unique_ptr<SceneSet> set(new SceneSet);
  const float h = mesh.voxel;
  const LeakMesh ground{"scene " + mesh.mesh.name + " ground", testing::boxMesh({0, 0, 0}, {120 * h, 60 * h, 10 * h}),
                        true};
  set->bodies_.push_back(bakeSubject(ground, mesh.mode, folder, out_error));
  if (!set->bodies_.back()) return nullptr;
  set->scenes_ = meshScenes(mesh, set->bodies_.back().get());
  return set;
}

std::unique_ptr<SceneSet> SceneSet::random(baker::NormalMode mode, int count, std::uint32_t seed, float speed,
                                           const std::string& folder, std::string* out_error) {
  std::unique_ptr<SceneSet> set(new SceneSet);
  if (!bakeBoxes({{"random ground", {60, 60, 2}, 132},
                  {"random crate", {4, 4, 4}, 32},
                  {"random rod", {1, 1, 8}, 28},
                  {"random slab", {10, 6, 0.75f}, 32}},
                 mode, folder, out_error, &set->bodies_))
    return nullptr;
  RandomScenes random{set->bodies_[0].get(),
                      {set->bodies_[1].get(), set->bodies_[2].get(), set->bodies_[3].get()},
                      speed,
                      std::mt19937(seed)};
  for (int n = 0; n < count; ++n)
    set->scenes_.push_back(random.next(n));
  return set;
}

} // namespace leak
} // namespace dng
