// The SIMD batch kernels against the scalar reference: for every instruction set this CPU has,
// View::sampleBatch and stepParticles must give bit for bit the scalar results, on dense and bricked
// fields, static and moving bodies, several bodies at once, every material rule and strided arrays.
#include "analytic_fields.h"
#include "dng/body_index.h"
#include "dng/format/writer.h"
#include "dng/instruction_set.h"
#include "dng/particles.h"
#include "swarm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace dng {
namespace {

using analytic::AnalyticField;

constexpr float kDt = 1.0f / 60.0f;
constexpr float kReachVoxels = 3.0f;

// What the file holds beside distances and normals: LIFT and GRAD (the accurate query reads them), or
// SHAD (the nearest and trilinear queries and the step's rules read it).
enum class Extras { kNone, kLift, kLiftAndGradient, kShading, kSecondPlanes };

// LIFT and GRAD sections whose values differ from the stored ones, as a 1.2 blurred bake's do: lifts of
// up to a third of a voxel, gradients tilted from the stored normals. Or SHAD tilted the same way, as
// a 1.3 blurred bake's.
void addExtras(Extras extras, format::DenseField* io) {
  if (extras == Extras::kNone) return;
  if (extras == Extras::kSecondPlanes) {
    // Planes lowered by up to half a voxel, and the unlowered ones beside them: alone, or every third as
    // a pair with the own plane raised back and the second one tilted, so that either of the two may be
    // the lower one and the other one may stop a walk first (the lanes step through pairs too).
    const float band = io->grid.band;
    io->second_distance.assign(io->distance.size(), -std::numeric_limits<float>::infinity());
    io->second_normal.assign(io->distance.size(), Vec3f{});
    io->second_raise.assign(io->distance.size(), -1.0f);
    for (std::size_t n = 0; n < io->distance.size(); ++n) {
      if (!(std::fabs(io->distance[n]) < band)) continue;
      const float lowering = 0.3f + 0.2f * std::sin(0.37f * float(n));
      io->second_distance[n] = io->distance[n] + (n % 3 == 0 ? 0.2f : 0.0f), io->second_normal[n] = io->normal[n];
      if (n % 3 == 0) {
        io->second_raise[n] = lowering;
        const Vec3f tilt{0.7f * std::cos(0.23f * float(n)), -0.6f, 0.7f * std::sin(0.19f * float(n))};
        io->second_normal[n] = normalizeOrZero(io->normal[n] + tilt);
      }
      io->distance[n] -= lowering;
    }
    return;
  }
  if (extras == Extras::kShading) {
    io->shading.resize(io->normal.size());
    for (std::size_t n = 0; n < io->normal.size(); ++n)
      io->shading[n] = normalizeOrZero(io->normal[n] + Vec3f{0.3f * std::cos(0.11f * float(n)), -0.2f, 0.1f});
    return;
  }
  const std::size_t count = io->distance.size();
  io->accurate.resize(count);
  for (std::size_t n = 0; n < count; ++n)
    io->accurate[n] = io->distance[n] + 0.33f * std::sin(0.37f * float(n));
  if (extras != Extras::kLiftAndGradient) return;
  io->gradient.resize(count);
  for (std::size_t n = 0; n < count; ++n)
    io->gradient[n] = normalizeOrZero(io->normal[n] + Vec3f{0.3f * std::cos(0.11f * float(n)), -0.2f, 0.1f});
}

// A 40^3 grid of unit voxels around the origin, dense or bricked.
struct Field {
  format::EncodeResult file;
  View view;
  Field(const AnalyticField& shape, bool dense, Extras extras = Extras::kNone) {
    format::DenseField samples =
        analytic::sampleField(analytic::cubeGrid({-20, -20, -20}, 1.0f, 40, kReachVoxels + 0.8661f), shape);
    addExtras(extras, &samples);
    file = dense ? format::encodeDense(samples, "") : format::encodeBricked(samples, {}, "");
    EXPECT_TRUE(file.ok()) << file.error;
    EXPECT_EQ(View::open(file.bytes.data(), file.bytes.size(), &view), Status::kOk);
  }
};

// Restores the process's choice when a test ends, whatever it chose.
struct ChosenSet {
  explicit ChosenSet(InstructionSet set) : before(activeInstructionSet()) {
    EXPECT_EQ(setInstructionSet(set), Status::kOk);
  }
  ~ChosenSet() { setInstructionSet(before); }
  InstructionSet before;
};

// The SIMD sets this build and machine can run: each is compared with the scalar path.
std::vector<InstructionSet> simdSets() {
  const InstructionSet before = activeInstructionSet();
  std::vector<InstructionSet> out;
  for (InstructionSet set : kInstructionSets) {
    if (set != InstructionSet::kScalar && setInstructionSet(set) == Status::kOk) out.push_back(set);
  }
  setInstructionSet(before);
  return out;
}

TEST(InstructionSet, TheBestSetIsChosenByDefault) {
  EXPECT_EQ(setInstructionSet(bestInstructionSet()), Status::kOk);
#if defined(__x86_64__) || defined(__aarch64__)
  EXPECT_FALSE(simdSets().empty()) << "x86-64 always has SSE4.1 here, aarch64 NEON";
  EXPECT_NE(bestInstructionSet(), InstructionSet::kScalar);
#endif
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

::testing::AssertionResult sameSample(const Sample& a, const Sample& b) {
  if (a.status == b.status && sameBits(a.distance, b.distance) && sameBits(a.normal.x, b.normal.x) &&
      sameBits(a.normal.y, b.normal.y) && sameBits(a.normal.z, b.normal.z))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "status " << unsigned(a.status) << " vs " << unsigned(b.status) << ", d "
                                       << a.distance << " vs " << b.distance << ", n (" << a.normal.x << ", "
                                       << a.normal.y << ", " << a.normal.z << ") vs (" << b.normal.x << ", "
                                       << b.normal.y << ", " << b.normal.z << ")";
}

TEST(InstructionSet, ChoosingOneTheMachineLacksFailsAndChangesNothing) {
  const InstructionSet before = activeInstructionSet();
  Diagnostic diag;
  EXPECT_EQ(setInstructionSet(InstructionSet(7), &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("not available"), std::string::npos);
  EXPECT_EQ(activeInstructionSet(), before);
  EXPECT_STREQ(instructionSetName(InstructionSet::kAvx2), "avx2");
  ChosenSet scalar(InstructionSet::kScalar);
  EXPECT_EQ(activeInstructionSet(), InstructionSet::kScalar);
}

// Points in and around the grid, a few of them not numbers at all, 16 bytes apart (xyz + padding).
std::vector<float> queryPoints(std::size_t count) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coord(-22.0f, 22.0f);
  std::vector<float> out(count * 4, 0.0f);
  for (std::size_t n = 0; n < count; ++n)
    for (int a = 0; a < 3; ++a)
      out[4 * n + std::size_t(a)] = coord(rng);
  out[4 * 5] = std::numeric_limits<float>::quiet_NaN();
  out[4 * 9 + 1] = std::numeric_limits<float>::infinity();
  return out;
}

TEST(InstructionSet, SampleBatchGivesTheScalarSamples) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  const AnalyticField sphere = analytic::sphereField({0.4f, -0.3f, 0.2f}, 12.0f);
  // 20,031 = 64 k + 32 + 31 = 16 k + 8 + 7 = 8 k + 4 + 3: pairs of registers, one register alone and a
  // tail, at 32, 8 and 4 lanes.
  const std::vector<float> points = queryPoints(20031);
  const std::size_t count = points.size() / 4;
  // The same points packed as Vec3f (12 bytes apart), which the x86 sets load with shuffles or lane
  // permutes.
  std::vector<float> packed;
  for (std::size_t n = 0; n < count; ++n)
    packed.insert(packed.end(), {points[4 * n], points[4 * n + 1], points[4 * n + 2]});
  const std::pair<const float*, std::size_t> layouts[] = {{points.data(), 16}, {packed.data(), sizeof(Vec3f)}};
  for (const AnalyticField* shape : {&box, &sphere}) {
    for (std::pair<bool, Extras> kind : {std::pair{false, Extras::kNone},
                                         {true, Extras::kNone},
                                         {false, Extras::kShading},
                                         {true, Extras::kShading}}) {
      const bool dense = kind.first;
      Field field(*shape, dense, kind.second);
      ASSERT_EQ(field.view.hasShading(), kind.second == Extras::kShading);
      for (Interpolation mode : {Interpolation::kNearest, Interpolation::kTrilinear, Interpolation::kAccurate}) {
        std::vector<Sample> reference(count), lanes(count);
        {
          ChosenSet scalar(InstructionSet::kScalar);
          field.view.sampleBatch(points.data(), 16, count, reference.data(), mode);
        }
        std::size_t in_band = 0;
        for (const Sample& s : reference)
          in_band += s.status == SampleStatus::kInBand ? 1 : 0;
        ASSERT_GT(in_band, count / 20) << "the points must meet the band, or the comparison says little";
        for (InstructionSet set : simdSets()) {
          ChosenSet chosen(set);
          for (const auto& [first, stride] : layouts) {
            std::fill(lanes.begin(), lanes.end(), Sample{-1.0f, Vec3f{2.0f, 3.0f, 4.0f}, SampleStatus::kInBand});
            field.view.sampleBatch(first, stride, count, lanes.data(), mode);
            for (std::size_t n = 0; n < count; ++n)
              ASSERT_TRUE(sameSample(lanes[n], reference[n]))
                  << instructionSetName(set) << ", mode " << unsigned(mode) << ", stride " << stride << ", point " << n;
          }
        }
      }
    }
  }
}

// The accurate query reads LIFT and GRAD where the file has them (per voxel, per plane tile, per pool
// word) and extends the stencil past the band's edge: the lanes must read the same entries.
TEST(InstructionSet, AccurateSampleBatchGivesTheScalarSamplesWithLiftAndGradient) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  const std::vector<float> points = queryPoints(20003);
  const std::size_t count = points.size() / 4;
  for (Extras extras : {Extras::kLift, Extras::kLiftAndGradient}) {
    for (bool dense : {false, true}) {
      Field field(box, dense, extras);
      ASSERT_TRUE(field.view.hasLift());
      ASSERT_EQ(field.view.hasGradient(), extras == Extras::kLiftAndGradient);
      std::vector<Sample> reference(count), plain(count), lanes(count);
      {
        ChosenSet scalar(InstructionSet::kScalar);
        field.view.sampleBatch(points.data(), 16, count, reference.data(), Interpolation::kAccurate);
        Field without(box, dense);
        without.view.sampleBatch(points.data(), 16, count, plain.data(), Interpolation::kAccurate);
      }
      std::size_t changed = 0; // the sections must change answers, or the comparison says little
      for (std::size_t n = 0; n < count; ++n)
        changed += reference[n].status == SampleStatus::kInBand && !sameSample(reference[n], plain[n]) ? 1 : 0;
      ASSERT_GT(changed, count / 20);
      for (InstructionSet set : simdSets()) {
        ChosenSet chosen(set);
        field.view.sampleBatch(points.data(), 16, count, lanes.data(), Interpolation::kAccurate);
        for (std::size_t n = 0; n < count; ++n)
          ASSERT_TRUE(sameSample(lanes[n], reference[n]))
              << instructionSetName(set) << (dense ? ", dense" : ", bricked") << ", extras " << int(extras)
              << ", point " << n;
      }
    }
  }
}

// Particles as an array of structures: positions and velocities interleaved with other data.
struct Particle {
  float position[3];
  float age;
  float velocity[3];
  float size;
};

struct Swarm {
  std::vector<Particle> particles;
  std::vector<std::uint8_t> contact;
  std::vector<std::int32_t> body;
  ParticleSpan span() {
    ParticleSpan s = testing::structSpan(&particles);
    s.out_contact = contact.data();
    s.out_body = body.data();
    return s;
  }
};

// Structure-of-arrays copy of the same particles: the packed fast path.
struct Packed {
  std::vector<float> px, py, pz, vx, vy, vz;
  std::vector<std::uint8_t> contact;
  std::vector<std::int32_t> body;
  explicit Packed(const Swarm& s) : contact(s.contact), body(s.body) {
    for (const Particle& p : s.particles) {
      px.push_back(p.position[0]), py.push_back(p.position[1]), pz.push_back(p.position[2]);
      vx.push_back(p.velocity[0]), vy.push_back(p.velocity[1]), vz.push_back(p.velocity[2]);
    }
  }
  ParticleSpan span() {
    ParticleSpan s;
    s.position_x = px.data(), s.position_y = py.data(), s.position_z = pz.data();
    s.velocity_x = vx.data(), s.velocity_y = vy.data(), s.velocity_z = vz.data();
    s.count = px.size();
    s.out_contact = contact.data();
    s.out_body = body.data();
    return s;
  }
};

// Particles anywhere from touching distance to beyond the band, moving at up to twice the design speed
// in random directions: some settled by one ball, many not.
Swarm randomSwarm(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-19.0f, 19.0f), unit(-1.0f, 1.0f);
  Swarm out;
  while (out.particles.size() < count) {
    const Vec3f v = normalizeOrZero({unit(rng), unit(rng), unit(rng)}) * (2.0f * kReachVoxels / kDt * unit(rng));
    const auto n = float(out.particles.size()); // age and size: bytes the step must leave alone
    out.particles.push_back({{coord(rng), coord(rng), coord(rng)}, n, {v.x, v.y, v.z}, -n});
  }
  out.contact.assign(count, 7);
  out.body.assign(count, 99);
  return out;
}

::testing::AssertionResult sameParticles(const Swarm& a, const Swarm& b) {
  for (std::size_t n = 0; n < a.particles.size(); ++n) {
    const Particle &p = a.particles[n], &q = b.particles[n];
    for (int c = 0; c < 3; ++c) {
      if (!sameBits(p.position[c], q.position[c]) || !sameBits(p.velocity[c], q.velocity[c]))
        return ::testing::AssertionFailure()
               << "particle " << n << " axis " << c << ": position " << p.position[c] << " vs " << q.position[c]
               << ", velocity " << p.velocity[c] << " vs " << q.velocity[c];
    }
    if (!sameBits(a.particles[n].age, b.particles[n].age) || !sameBits(a.particles[n].size, b.particles[n].size))
      return ::testing::AssertionFailure() << "particle " << n << ": age/size differ";
    if (a.contact[n] != b.contact[n] || a.body[n] != b.body[n])
      return ::testing::AssertionFailure() << "particle " << n << ": contact/body differ";
  }
  return ::testing::AssertionSuccess();
}

void copyBack(const Packed& packed, Swarm* io) {
  for (std::size_t n = 0; n < io->particles.size(); ++n) {
    Particle& p = io->particles[n];
    p.position[0] = packed.px[n], p.position[1] = packed.py[n], p.position[2] = packed.pz[n];
    p.velocity[0] = packed.vx[n], p.velocity[1] = packed.vy[n], p.velocity[2] = packed.vz[n];
  }
  io->contact = packed.contact;
  io->body = packed.body;
}

// stepParticles with the index when there is one.
Status stepWith(const ParticleSpan& span, const std::vector<Body>& bodies, const BodyIndex* index) {
  if (index != nullptr) return stepParticles(span, kDt, bodies.data(), bodies.size(), *index);
  return stepParticles(span, kDt, bodies.data(), bodies.size());
}

// Steps the same particles with the scalar path (strided) and with each SIMD set (strided and packed),
// comparing everything after every step; through `index` when it is not null.
void expectSameSteps(const std::vector<Body>& bodies, const Swarm& start, const BodyIndex* index = nullptr) {
  for (InstructionSet set : simdSets()) {
    Swarm reference = start, strided = start;
    Packed packed(start);
    for (int step = 0; step < 25; ++step) {
      {
        ChosenSet scalar(InstructionSet::kScalar);
        ASSERT_EQ(stepWith(reference.span(), bodies, index), Status::kOk);
      }
      ChosenSet chosen(set);
      ASSERT_EQ(stepWith(strided.span(), bodies, index), Status::kOk);
      ASSERT_EQ(stepWith(packed.span(), bodies, index), Status::kOk);
      ASSERT_TRUE(sameParticles(strided, reference)) << instructionSetName(set) << " strided, step " << step;
      Swarm from_packed = start;
      copyBack(packed, &from_packed);
      ASSERT_TRUE(sameParticles(from_packed, reference)) << instructionSetName(set) << " packed, step " << step;
    }
  }
}

void expectSameSteps(const std::vector<Body>& bodies, std::uint32_t seed) {
  expectSameSteps(bodies, randomSwarm(3001, seed));
}

Body makeBody(const View& view, const Material& material) {
  Body body;
  EXPECT_EQ(Body::create(&view, material, &body), Status::kOk);
  return body;
}

Material everyRule() {
  Material m;
  m.restitution = 0.4f;
  m.collision_distance = 0.2f;
  m.drag = 2.0f;
  m.contact_distance = 1.0f;
  m.flow_in = 30.0f;
  m.flow_out = -10.0f;
  m.flow_distance = 2.0f;
  return m;
}

// The other materials the multi-body scenes mix in: a spring with drag, everyRule swept, and a body
// that only drags and steers (kNone: never walked through).
struct OtherMaterials {
  Material spring, swept, ghost;
};

OtherMaterials otherMaterials() {
  OtherMaterials m;
  m.spring.response = Response::kSpring;
  m.spring.drag = 1.0f;
  m.spring.contact_distance = 2.0f;
  m.swept = everyRule();
  m.swept.swept = true;
  m.ghost.response = Response::kNone;
  m.ghost.drag = 3.0f;
  m.ghost.contact_distance = 2.0f;
  return m;
}

TEST(InstructionSet, StepGivesTheScalarResultsOnAStaticBody) {
  const AnalyticField sphere = analytic::sphereField({0.4f, -0.3f, 0.2f}, 12.0f);
  for (bool dense : {false, true}) {
    Field field(sphere, dense);
    expectSameSteps({makeBody(field.view, Material{})}, 11);
    expectSameSteps({makeBody(field.view, everyRule())}, 12);
  }
}

// `count` particles at points of the cube [-12, 12]^3 that `pick` takes. `pick(p, rng, &position,
// &velocity)` draws what more it needs from `rng` and returns false to pass `p` over. A test fails when
// 20 million points do not give `count`.
template <class Pick> Swarm pickedSwarm(std::size_t count, std::uint32_t seed, Pick pick) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(-12.0f, 12.0f);
  Swarm out;
  for (int tries = 0; tries < 20000000 && out.particles.size() < count; ++tries) {
    const Vec3f p{coord(rng), coord(rng), coord(rng)};
    Vec3f position, v;
    if (!pick(p, rng, &position, &v)) continue;
    out.particles.push_back({{position.x, position.y, position.z}, 0.0f, {v.x, v.y, v.z}, 0.0f});
  }
  if (out.particles.size() < count) ADD_FAILURE() << "only " << out.particles.size() << " of " << count << " points";
  out.contact.assign(out.particles.size(), 7);
  out.body.assign(out.particles.size(), 99);
  return out;
}

// `swarm` after one step past `body`, with the set chosen now.
Swarm steppedOnce(Swarm swarm, const Body& body) {
  EXPECT_EQ(stepParticles(swarm.span(), kDt, &body, 1), Status::kOk);
  return swarm;
}

// A velocity in a random direction at up to one voxel per step.
Vec3f randomVelocity(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  return normalizeOrZero({unit(rng), unit(rng), unit(rng)}) * (1.0f / kDt * std::fabs(unit(rng)));
}

// How many particles of `after` lie at least `by` (summed over the axes) from where they were in `before`.
std::size_t movedCount(const Swarm& before, const Swarm& after, float by) {
  std::size_t moved = 0;
  for (std::size_t n = 0; n < before.particles.size(); ++n) {
    const float* a = before.particles[n].position;
    const float* b = after.particles[n].position;
    moved += !(std::fabs(a[0] - b[0]) + std::fabs(a[1] - b[1]) + std::fabs(a[2] - b[2]) < by);
  }
  return moved;
}

// `count` particles 0.05 to 0.4 out from `shape`'s surface, moving along it (the normal's part mostly
// removed) at half to one voxel per step: their balls rarely settle a move.
Swarm skimmingSwarm(const AnalyticField& shape, std::size_t count, std::uint32_t seed) {
  return pickedSwarm(count, seed, [&](Vec3f p, std::mt19937& rng, Vec3f* out_position, Vec3f* out_velocity) {
    const analytic::Exact at = shape(p);
    if (!(at.distance > 0.05f && at.distance < 0.4f)) return false;
    // Along the surface (the normal's part removed), with a little of it towards or away.
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const Vec3f random{unit(rng), unit(rng), unit(rng)};
    const Vec3f along = normalizeOrZero(random - at.normal * (dot(random, at.normal) * 0.9f));
    *out_position = p;
    *out_velocity = along * (1.0f / kDt * (0.5f + 0.5f * std::fabs(unit(rng))));
    return true;
  });
}

// A SHAD section: the rules read its normals, the walk the planes'. Every rule, both encodings; the
// shading must change the results, or the comparison says little.
TEST(InstructionSet, StepGivesTheScalarResultsWithShadingNormals) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  for (bool dense : {false, true}) {
    Field shaded(box, dense, Extras::kShading), plain(box, dense);
    ASSERT_TRUE(shaded.view.hasShading());
    expectSameSteps({makeBody(shaded.view, everyRule())}, 15);
    const Body on_shaded = makeBody(shaded.view, everyRule()), on_plain = makeBody(plain.view, everyRule());
    Swarm a = randomSwarm(3001, 15), b = a;
    ASSERT_EQ(stepParticles(a.span(), kDt, &on_shaded, 1), Status::kOk);
    ASSERT_EQ(stepParticles(b.span(), kDt, &on_plain, 1), Status::kOk);
    EXPECT_FALSE(sameParticles(a, b));
  }
}

// A PLN2 section: the walk reads the second planes where the lowered first ones stop it or prove
// nothing. Particles skimming the faces, where that happens; the planes must change the results.
TEST(InstructionSet, StepGivesTheScalarResultsWithSecondPlanes) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field seconded(box, false, Extras::kSecondPlanes);
  ASSERT_TRUE(seconded.view.hasSecondPlanes());
  Swarm skimming = skimmingSwarm(box, 2001, 22);
  expectSameSteps({makeBody(seconded.view, everyRule())}, skimming);
  // The same lowered planes without the second ones.
  format::DenseField lowered =
      analytic::sampleField(analytic::cubeGrid({-20, -20, -20}, 1.0f, 40, kReachVoxels + 0.8661f), box);
  addExtras(Extras::kSecondPlanes, &lowered);
  lowered.second_distance.clear(), lowered.second_normal.clear(), lowered.second_raise.clear();
  const format::EncodeResult plain = format::encodeBricked(lowered, {}, "");
  View plain_view;
  ASSERT_EQ(View::open(plain.bytes.data(), plain.bytes.size(), &plain_view), Status::kOk);
  const Body on_seconded = makeBody(seconded.view, everyRule()), on_plain = makeBody(plain_view, everyRule());
  Swarm a = skimming, b = skimming;
  ASSERT_EQ(stepParticles(a.span(), kDt, &on_seconded, 1), Status::kOk);
  ASSERT_EQ(stepParticles(b.span(), kDt, &on_plain, 1), Status::kOk);
  EXPECT_FALSE(sameParticles(a, b));
}

// Particles skimming a box's faces and edges, under half a voxel out, at half to one voxel per step:
// their balls rarely settle a move, so most walks are set aside and walked cell by cell together
// (runtime/src/span_lanes.h), hundreds of them per call (several batches, the last one partial).
TEST(InstructionSet, StepGivesTheScalarResultsWhenMostWalksGoCellByCell) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field field(box, false);
  expectSameSteps({makeBody(field.view, everyRule())}, skimmingSwarm(box, 2001, 21));
}

// Without an index the kernels take each chunk's response samples one chunk ahead (span_lanes.h
// stepEveryBody): spans from one particle to a few chunks of the widest set, at and beside each set's
// chunk size (4, 16, 32) and its multiples, so that the first, the last and the lone chunk, and the
// tails after them, all meet the surface.
TEST(InstructionSet, StepGivesTheScalarResultsForSpansAroundEachChunkSize) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field field(box, false, Extras::kShading);
  const Swarm skimming = skimmingSwarm(box, 100, 23);
  for (std::size_t count : {1, 3, 4, 5, 15, 16, 17, 31, 32, 33, 47, 63, 64, 65, 96, 97, 100}) {
    Swarm first = skimming;
    first.particles.resize(count), first.contact.resize(count), first.body.resize(count);
    expectSameSteps({makeBody(field.view, everyRule())}, first);
  }
}

// `count` particles within 0.3 voxel of the surface of `shape`, `body`'s field, that the body cannot prove
// outside (Body::provesOutside), moving at up to one voxel per step in random directions: the walk
// blocks each where it stands, and the kernels settle that stop without handing the walk over.
Swarm unprovenSwarm(const AnalyticField& shape, const Body& body, std::size_t count, std::uint32_t seed) {
  return pickedSwarm(count, seed, [&](Vec3f local, std::mt19937& rng, Vec3f* out_position, Vec3f* out_velocity) {
    if (!(std::fabs(shape(local).distance) < 0.3f)) return false;
    *out_position = body.toWorld(local);
    if (body.provesOutside(*out_position)) return false;
    *out_velocity = randomVelocity(rng);
    return true;
  });
}

TEST(InstructionSet, StepGivesTheScalarResultsForParticlesTheFieldCannotProveOutside) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field field(box, false);
  const Body still = makeBody(field.view, everyRule());
  const Swarm unproven = unprovenSwarm(box, still, 1001, 31);
  expectSameSteps({still}, unproven);
  // Most of them are blocked, so the comparison covers that stop: they do not move.
  const std::size_t stayed = unproven.particles.size() - movedCount(unproven, steppedOnce(unproven, still), 1e-4f);
  EXPECT_GT(stayed, unproven.particles.size() / 2);
  // On a moving body a blocked particle is carried with it.
  Body moving = still;
  const float quaternion[4] = {0.9f, 0.1f, -0.3f, 0.2f};
  ASSERT_EQ(moving.setTransform({1.0f, -2.0f, 0.5f}, quaternion, 0.8f), Status::kOk);
  moving.setVelocity({30.0f, -12.0f, 5.0f}, {0.5f, 2.0f, -1.0f});
  expectSameSteps({moving}, unprovenSwarm(box, moving, 1001, 32));
}

// `count` particles just outside `shape` that only the cells around them prove outside: their own
// cell's planes read below a hundredth of a voxel (View::lowerBound; beside a convex edge, the other
// face's plane), but Body::provesOutside holds. They move at up to one voxel per step in random
// directions.
Swarm neighbourProvenSwarm(const AnalyticField& shape, const Body& body, std::size_t count, std::uint32_t seed) {
  const float proof_level = 0.01f * body.field()->grid().voxel_size;
  return pickedSwarm(count, seed, [&](Vec3f p, std::mt19937& rng, Vec3f* out_position, Vec3f* out_velocity) {
    if (!(shape(p).distance > 0.0f && shape(p).distance < 0.5f)) return false;
    if (!(body.field()->lowerBound(p).distance < proof_level) || !body.provesOutside(p)) return false;
    *out_position = p;
    *out_velocity = randomVelocity(rng);
    return true;
  });
}

// Where a start's own planes prove nothing, the walk takes the neighbours' bound there and, where it
// leaves room, walks on by its ball or the neighbour's plane. The kernels take that bound in lanes and
// hand the walk over with it (the scalar walk reads it instead of taking it again), so the comparison
// covers the handed bound as well as the walk that follows it.
TEST(InstructionSet, StepGivesTheScalarResultsWhereOnlyTheNeighboursProveAStart) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field field(box, false);
  const Body still = makeBody(field.view, everyRule());
  const Swarm proven = neighbourProvenSwarm(box, still, 1001, 33);
  expectSameSteps({still}, proven);
  // Most of them walk on from the bound: they move.
  EXPECT_GT(movedCount(proven, steppedOnce(proven, still), 1e-3f), proven.particles.size() / 2);
}

TEST(InstructionSet, StepGivesTheScalarResultsOnAMovingSpinningScaledBody) {
  const AnalyticField box = analytic::boxField({0.3f, 0.2f, -0.1f}, {9.0f, 7.0f, 11.0f});
  Field field(box, false);
  Body body = makeBody(field.view, everyRule());
  const float quaternion[4] = {0.9f, 0.1f, -0.3f, 0.2f};
  ASSERT_EQ(body.setTransform({1.0f, -2.0f, 0.5f}, quaternion, 0.8f), Status::kOk);
  body.setVelocity({30.0f, -12.0f, 5.0f}, {0.5f, 2.0f, -1.0f});
  expectSameSteps({body}, 13);
}

TEST(InstructionSet, StepGivesTheScalarResultsWithSeveralBodiesAndEveryResponse) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  const AnalyticField box = analytic::boxField({0, 0, 0}, {5.0f, 5.0f, 5.0f});
  Field sphere_field(sphere, false), box_field(box, true);
  const OtherMaterials m = otherMaterials();
  std::vector<Body> bodies{makeBody(sphere_field.view, Material{}), makeBody(box_field.view, m.spring),
                           makeBody(sphere_field.view, m.swept), makeBody(box_field.view, m.ghost)};
  const float identity[4] = {1, 0, 0, 0};
  const Vec3f places[] = {{-9, 0, 0}, {9, 2, 0}, {0, 10, 3}, {0, -9, -2}};
  for (std::size_t b = 0; b < bodies.size(); ++b)
    ASSERT_EQ(bodies[b].setTransform(places[b], identity, 0.9f), Status::kOk);
  bodies[2].setVelocity({0, -20.0f, 0}, {0, 0, 1.5f});
  expectSameSteps(bodies, 14);
}

// More bodies than the kernels take without an index: the chunks of lanes find theirs through it. A
// lattice of overlapping bodies (moving, spinning, scaled; dense and bricked; every response), small
// bodies scattered between them, a cluster of more bodies than a chunk lists (its lanes go to the
// scalar path), and particles fast enough that their moves cross several cells.
TEST(InstructionSet, StepGivesTheScalarResultsWithManyBodiesThroughAnIndex) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  const AnalyticField box = analytic::boxField({0, 0, 0}, {5.0f, 6.0f, 4.0f});
  Field sphere_field(sphere, false), box_field(box, true);
  const OtherMaterials m = otherMaterials();
  const Material materials[] = {Material{}, everyRule(), m.spring, m.swept, m.ghost};
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Body> bodies;
  for (int b = 0; b < 60; ++b) { // 5 x 4 x 3, 8 apart: neighbours' boxes overlap
    const View& view = b % 3 == 0 ? box_field.view : sphere_field.view;
    Body body = makeBody(view, materials[b % 5]);
    const float q[4] = {1.0f, 0.3f * unit(rng), 0.3f * unit(rng), 0.3f * unit(rng)};
    const Vec3f at{8.0f * float(b % 5) - 16.0f, 8.0f * float((b / 5) % 4) - 12.0f, 8.0f * float(b / 20) - 8.0f};
    ASSERT_EQ(body.setTransform(at, q, 0.25f + 0.05f * float(b % 4)), Status::kOk);
    if (b % 4 == 1) body.setVelocity({20.0f * unit(rng), 20.0f * unit(rng), 20.0f * unit(rng)}, {0, 0, 0});
    if (b % 4 == 2) body.setVelocity({0, 0, 0}, {2.0f * unit(rng), 2.0f * unit(rng), 2.0f * unit(rng)});
    bodies.push_back(body);
  }
  for (int b = 0; b < 20; ++b) { // more than a chunk can list, all at one place
    Body body = makeBody(sphere_field.view, materials[b % 5]);
    const float identity[4] = {1, 0, 0, 0};
    ASSERT_EQ(body.setTransform({2.0f + 0.1f * float(b), -3.0f, 1.0f}, identity, 0.2f), Status::kOk);
    bodies.push_back(body);
  }
  std::uniform_real_distribution<float> anywhere(-18.0f, 18.0f);
  for (int b = 0; b < 60; ++b) { // small ones, each in a few cells: moves reach them across cell walls
    Body body = makeBody(b % 2 == 0 ? box_field.view : sphere_field.view, materials[b % 5]);
    const float identity[4] = {1, 0, 0, 0};
    ASSERT_EQ(body.setTransform({anywhere(rng), anywhere(rng), anywhere(rng)}, identity, 0.06f), Status::kOk);
    bodies.push_back(body);
  }
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  Swarm swarm = randomSwarm(3001, 15);
  for (std::size_t n = 0; n < swarm.particles.size(); n += 50) { // some 25 times faster
    for (float& v : swarm.particles[n].velocity)
      v *= 25.0f;
  }
  // Every other group of 8 close together, as particles kept in spatial order are: their chunks share
  // bodies and step in lanes (a lane alone near a body goes to the scalar path).
  for (std::size_t n = 0; n < swarm.particles.size(); ++n) {
    const std::size_t first = n - n % 8;
    if (first % 16 != 0 || n == first) continue;
    for (int c = 0; c < 3; ++c)
      swarm.particles[n].position[c] = swarm.particles[first].position[c] + 0.1f * unit(rng);
  }
  expectSameSteps(bodies, swarm, &index);
}

// 150 bodies of `view`'s field on a 5 x 5 x 5 lattice 8 apart (the last 25 overlap the first ones,
// 1.5 off, so that lanes have two bodies), turned and scaled; a third static, a third moving (some fast
// enough to sweep their grids' margins in a step), a third spinning. Every `spring_every`-th body
// springs (the spring reads the band); the others take every rule.
std::vector<Body> bodyLattice(const View& view, int spring_every, std::mt19937* rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const Material spring = otherMaterials().spring;
  std::vector<Body> bodies;
  for (int b = 0; b < 150; ++b) {
    Body body = makeBody(view, b % spring_every == spring_every - 1 ? spring : everyRule());
    const int cell = b % 125;
    Vec3f at{8.0f * float(cell % 5) - 16.0f, 8.0f * float((cell / 5) % 5) - 16.0f, 8.0f * float(cell / 25) - 16.0f};
    if (b >= 125) at = at + Vec3f{1.5f, -1.0f, 0.5f};
    const float q[4] = {1.0f, 0.4f * unit(*rng), 0.4f * unit(*rng), 0.4f * unit(*rng)};
    EXPECT_EQ(body.setTransform(at, q, 0.12f + 0.02f * unit(*rng)), Status::kOk);
    const float speed = b % 6 == 1 ? 200.0f : 40.0f;
    const Vec3f spin{9.0f * unit(*rng), 9.0f * unit(*rng), 9.0f * unit(*rng)};
    const Vec3f move = Vec3f{unit(*rng), unit(*rng), unit(*rng)} * speed;
    if (b % 3 == 1) body.setVelocity(move, {0, 0, 0});
    if (b % 3 == 2) body.setVelocity({0, 0, 0}, spin);
    bodies.push_back(body);
  }
  return bodies;
}

// Places the particles near a random body each, slow: the even ones in its box, the odd ones just past
// the face its move heads for (outside the box, where only the body's travel in the step brings them
// near, and its surface sweeps some).
void placeNearBodies(const std::vector<Body>& bodies, Swarm* swarm, std::mt19937* rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick(0, bodies.size() - 1);
  for (std::size_t n = 0; n < swarm->particles.size(); ++n) {
    Particle& p = swarm->particles[n];
    const Body& near = bodies[pick(*rng)];
    const Vec3f lo = near.boundsMin(), hi = near.boundsMax(), v = near.linearVelocity();
    int ahead = n % 2 == 0 ? -1 : 0; // the axis of the move's largest part
    for (int c = 1; c < 3 && ahead >= 0; ++c)
      if (std::fabs((&v.x)[c]) > std::fabs((&v.x)[ahead])) ahead = c;
    for (int c = 0; c < 3; ++c) {
      const float mid = 0.5f * ((&lo.x)[c] + (&hi.x)[c]), half = 0.5f * ((&hi.x)[c] - (&lo.x)[c]);
      const float vc = (&v.x)[c], past = (half + 0.3f * std::fabs(vc) * kDt) * (vc < 0.0f ? -1.0f : 1.0f);
      p.position[c] = mid + (c == ahead && vc != 0.0f ? past : 0.9f * half * unit(*rng));
      p.velocity[c] *= 0.05f;
    }
  }
}

// A chunk whose lanes each meet their own bodies, all of one field and one material, steps them in one
// pass per slot, each lane with its own body's numbers gathered (slot_lanes.h); where a slot mixes
// materials or fields the chunk goes the union way. Every seventh body springs, or all do (then slots
// of different spring bodies, which read their own bands, are common); particles in random order.
TEST(InstructionSet, StepGivesTheScalarResultsWhenEachLaneMeetsItsOwnBody) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  const AnalyticField box = analytic::boxField({0, 0, 0}, {5.0f, 6.0f, 4.0f});
  for (const int spring_every : {7, 1}) {
    for (const bool dense : {false, true}) {
      SCOPED_TRACE(std::string(dense ? "dense" : "bricked") + ", every " + std::to_string(spring_every));
      Field field(dense ? box : sphere, dense);
      std::mt19937 rng(31);
      const std::vector<Body> bodies = bodyLattice(field.view, spring_every, &rng);
      BodyIndex index;
      ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
      Swarm swarm = randomSwarm(3001, 32);
      placeNearBodies(bodies, &swarm, &rng);
      expectSameSteps(bodies, swarm, &index);
    }
  }
}

// Materials may change after the index's build: the bodies of one kind at the build (one field, one
// material, stepped together, slot_lanes.h) then differ, and the kernels must not step them as one. The
// lattice of bodies near which each lane meets its own, with a quarter of its bodies turned to springs
// and its springs to a bouncier impact after the rebuild; the index is not rebuilt.
TEST(InstructionSet, StepGivesTheScalarResultsWhenMaterialsChangeAfterTheIndexIsBuilt) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  Field field(sphere, false);
  std::mt19937 rng(41);
  std::vector<Body> bodies = bodyLattice(field.view, 7, &rng);
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  Material bouncy = everyRule();
  bouncy.restitution = 0.9f;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Material now = b % 4 == 0 ? otherMaterials().spring : b % 7 == 6 ? bouncy : bodies[b].material();
    ASSERT_EQ(bodies[b].setMaterial(now), Status::kOk);
  }
  Swarm swarm = randomSwarm(3001, 42);
  placeNearBodies(bodies, &swarm, &rng);
  expectSameSteps(bodies, swarm, &index);
}

// Through an index, the lanes of a chunk that meet a body are queued when they are at most half of it,
// and stepped together once the queue holds a chunk's worth, gathered from several chunks; the others
// move at once (span_lanes.h, Crowded). A city of 400 small bodies, some moving, a few turned, over a
// flat lattice; particles in random order over it, most of them near no body (about one in ten meets
// one). A lane left out of a queue, stepped twice, or listed without a body it meets (the cells' coarse
// boxes, broadphase.h cell_box) would differ from the scalar path.
TEST(InstructionSet, StepGivesTheScalarResultsWhenFewLanesOfEachChunkMeetABody) {
  const AnalyticField box = analytic::boxField({0, 0, 0}, {5.0f, 6.0f, 4.0f});
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  Field box_field(box, true), sphere_field(sphere, false);
  std::mt19937 rng(37);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<Body> bodies;
  for (int b = 0; b < 400; ++b) { // 20 x 20, 6 apart, boxes about 2 wide
    Body body = makeBody(b % 5 == 4 ? sphere_field.view : box_field.view, b % 7 == 3 ? everyRule() : Material{});
    const float turned[4] = {1.0f, 0.2f * unit(rng), 0.2f * unit(rng), 0.2f * unit(rng)};
    const float identity[4] = {1, 0, 0, 0};
    const Vec3f at{6.0f * float(b % 20) - 57.0f + unit(rng), 6.0f * float(b / 20) - 57.0f + unit(rng),
                   0.5f * unit(rng)};
    ASSERT_EQ(body.setTransform(at, b % 3 == 0 ? turned : identity, 0.06f + 0.02f * unit(rng)), Status::kOk);
    if (b % 4 == 1) body.setVelocity({6.0f * unit(rng), 6.0f * unit(rng), 3.0f * unit(rng)}, {0, 0, 0});
    bodies.push_back(body);
  }
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  Swarm swarm = randomSwarm(4001, 38);
  std::uniform_real_distribution<float> across(-60.0f, 60.0f);
  std::size_t meeting = 0;
  for (Particle& p : swarm.particles) {
    p.position[0] = across(rng), p.position[1] = across(rng), p.position[2] = 2.5f * unit(rng);
    for (float& v : p.velocity)
      v *= 0.1f;
    const Vec3f at{p.position[0], p.position[1], p.position[2]};
    std::uint32_t near[4];
    meeting += index.bodiesNear(at, at, near, 4) > 0 ? 1 : 0;
  }
  // Few enough that chunks queue them, and enough to fill several queues.
  EXPECT_GT(meeting, swarm.particles.size() / 20);
  EXPECT_LT(meeting, swarm.particles.size() / 4);
  expectSameSteps(bodies, swarm, &index);
}

// Moves over several cells of the index list the bodies of every cell they cross: groups of 8
// particles (a chunk of lanes) cross three walls of the index's cells at once, each group towards a
// small body that stands just past the first, second or third of those walls (so none of the cells
// before it lists it), along each axis both ways. A chunk that listed fewer cells than its moves cross
// would let its lanes pass through the body where the scalar path stops them.
TEST(InstructionSet, StepGivesTheScalarResultsWhenMovesCrossCellsOfAnIndex) {
  const AnalyticField sphere = analytic::sphereField({0, 0, 0}, 8.0f);
  const AnalyticField box = analytic::boxField({0, 0, 0}, {5.0f, 6.0f, 4.0f});
  Field sphere_field(sphere, false), box_field(box, true);
  Material ghost; // the frame: no response, never walked through
  ghost.response = Response::kNone;
  const float identity[4] = {1, 0, 0, 0};
  // The frame's box, [-20, 20] on every axis, is the scene's box; with 125 bodies the index cuts it
  // into cubes of about 4 cells per body (broadphase.cpp cellEdge): 8 along each axis, of 40 / 500^(1/3).
  std::vector<Body> bodies{makeBody(sphere_field.view, ghost)};
  constexpr int kGroups = 124, kCells = 8;
  const float edge = float(40.0 / std::cbrt(4.0 * (kGroups + 1)));
  constexpr float kMove = 16.0f; // from 1 past a wall to 2 past the third wall after it (edges over 4.5)
  auto wall = [&](int k) { return -20.0f + edge * float(k); };
  std::mt19937 rng(23);
  std::uniform_int_distribution<int> cell(0, kCells - 1), start_cell(3, 4); // 3 walls either way
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Swarm swarm = randomSwarm(kGroups * 8, 24);
  for (int group = 0; group < kGroups; ++group) {
    const int axis = group % 3, ahead = 1 + (group / 6) % 3;
    const float sign = (group / 3) % 2 == 0 ? 1.0f : -1.0f;
    const int i = start_cell(rng);
    Vec3f centre{wall(cell(rng)) + 0.5f * edge, wall(cell(rng)) + 0.5f * edge, wall(cell(rng)) + 0.5f * edge};
    Vec3f at = centre; // the body: its box of 2 from 0.2 to 2.2 past the wall
    float* start = &centre.x + axis;
    float* body_at = &at.x + axis;
    *start = sign > 0 ? wall(i) + 1.0f : wall(i + 1) - 1.0f;
    *body_at = sign > 0 ? wall(i + ahead) + 1.2f : wall(i + 1 - ahead) - 1.2f;
    Body body = makeBody(box_field.view, Material{});
    ASSERT_EQ(body.setTransform(at, identity, 0.05f), Status::kOk);
    bodies.push_back(body);
    for (int lane = 0; lane < 8; ++lane) { // within the body's cross-section, 0.4 by at least 0.4
      Particle& p = swarm.particles[std::size_t(group * 8 + lane)];
      for (int c = 0; c < 3; ++c) {
        p.position[c] = (&centre.x)[c] + (c == axis ? 0.2f : 0.1f) * unit(rng);
        p.velocity[c] = c == axis ? sign * kMove / kDt : 0.0f;
      }
    }
  }
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  std::uint32_t dims[3];
  index.cellDims(dims);
  for (std::uint32_t d : dims)
    ASSERT_EQ(d, std::uint32_t(kCells));
  expectSameSteps(bodies, swarm, &index);
}

// A chunk lists its moves' bodies in the same cell walk as its responses' (near_lanes.h), for the
// velocities before the responses; the lanes whose velocities the responses change are listed again.
// Groups of 8 particles (a chunk) just off the faces of a large box that bounces them straight back
// (restitution 1), towards a small body that their moves before the bounce do not reach. A chunk that
// kept the first list would let its lanes pass through that body, where the scalar path stops them.
TEST(InstructionSet, StepGivesTheScalarResultsWhenResponsesTurnMovesInAnIndex) {
  const Vec3f half{5.0f, 6.0f, 4.0f};
  const AnalyticField box = analytic::boxField({0, 0, 0}, half);
  Field box_field(box, true);
  Material bouncy;
  bouncy.restitution = 1.0f;
  std::vector<Body> bodies{makeBody(box_field.view, bouncy)}; // at the origin, its grid [-20, 20]^3
  const float identity[4] = {1, 0, 0, 0};
  constexpr int kGroups = 24;
  constexpr float kMove = 8.0f;
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Swarm swarm = randomSwarm(kGroups * 8, 30);
  for (int group = 0; group < kGroups; ++group) {
    const int axis = group % 3;
    const float sign = (group / 3) % 2 == 0 ? 1.0f : -1.0f; // the face, and the way the bounce sends them
    Vec3f centre;
    for (int c = 0; c < 3; ++c) // on the face, away from its edges; 0.5 off it, well within its band
      (&centre.x)[c] = c == axis ? sign * ((&half.x)[c] + 0.5f) : ((&half.x)[c] - 1.5f) * unit(rng);
    Vec3f target_at = centre;
    (&target_at.x)[axis] += sign * 0.5f * kMove; // its box reaches 1 either way, its face 0.25 at most
    Body target = makeBody(box_field.view, Material{});
    ASSERT_EQ(target.setTransform(target_at, identity, 0.05f), Status::kOk);
    bodies.push_back(target);
    for (int lane = 0; lane < 8; ++lane) { // within the small body's cross-section
      Particle& p = swarm.particles[std::size_t(group * 8 + lane)];
      for (int c = 0; c < 3; ++c) {
        p.position[c] = (&centre.x)[c] + (c == axis ? 0.02f : 0.1f) * unit(rng);
        p.velocity[c] = c == axis ? -sign * kMove / kDt : 0.0f;
      }
    }
  }
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  expectSameSteps(bodies, swarm, &index);
}

} // namespace
} // namespace dng
