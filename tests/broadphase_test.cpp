// The broadphase (dng/body_index.h): stepping through it gives bit for bit what stepping every body
// gives, on random scenes of moving, turning bodies of very different sizes; it lists few bodies per
// particle; and a stale or mismatched index is refused without touching a particle.
#include "analytic_fields.h"
#include "dng/body_index.h"
#include "dng/forces.h"
#include "dng/format/writer.h"
#include "swarm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace dng {
namespace {

using analytic::AnalyticField;
using Particles = testing::Swarm;

constexpr float kDt = 1.0f / 60.0f;

// A field sampled from an analytic shape into a 24^3 grid of unit voxels, [-12, 12)^3, band 3 voxels
// plus the half-diagonal guard.
struct Field {
  format::EncodeResult file;
  View view;
  explicit Field(const AnalyticField& shape) {
    file = format::encodeBricked(analytic::sampleField(analytic::cubeGrid({-12, -12, -12}, 1.0f, 24, 3.8661f), shape),
                                 {}, "");
    EXPECT_TRUE(file.ok()) << file.error;
    EXPECT_EQ(View::open(file.bytes.data(), file.bytes.size(), &view), Status::kOk);
  }
};

struct Fields {
  Field sphere{analytic::sphereField({0.2f, -0.1f, 0.3f}, 8.0f)};
  Field box{analytic::boxField({0.1f, 0.2f, -0.1f}, {6.0f, 5.0f, 7.0f})};
  Field slab{analytic::boxField({0.0f, 0.0f, 0.0f}, {11.0f, 11.0f, 3.0f})}; // a ground when scaled up
};

const Fields& fields() {
  static const Fields* f = new Fields;
  return *f;
}

// A body and how it moves: the test carries its pose through the steps as an engine would.
struct Mover {
  Body body;
  Vec3f position, velocity, axis{0, 0, 1};
  float angle = 0.0f, spin = 0.0f, scale = 1.0f;

  void place() {
    const float q[4] = {std::cos(0.5f * angle), axis.x * std::sin(0.5f * angle), axis.y * std::sin(0.5f * angle),
                        axis.z * std::sin(0.5f * angle)};
    ASSERT_EQ(body.setTransform(position, q, scale), Status::kOk);
    body.setVelocity(velocity, axis * spin);
  }
  void advance(float dt) {
    position = position + velocity * dt;
    angle += spin * dt;
    place();
  }
};

Material randomMaterial(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Material m;
  const float pick = unit(rng);
  m.response = pick < 0.6f ? Response::kImpact : pick < 0.85f ? Response::kSpring : Response::kNone;
  m.restitution = unit(rng);
  m.collision_distance = 0.1f + 0.3f * unit(rng);
  if (unit(rng) < 0.4f) m.drag = 3.0f * unit(rng), m.contact_distance = 1.0f;
  if (unit(rng) < 0.3f) m.flow_in = 10.0f * unit(rng), m.flow_out = 2.0f, m.flow_distance = 2.0f;
  m.swept = unit(rng) < 0.2f;
  return m;
}

// A ground slab 220 wide (top at z = 0) and `count - 1` bodies between 0.1 and 1.5 times the size of
// their 24-unit grids above it: a third at rest, a third sliding, a third sliding and turning.
std::vector<Mover> randomScene(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto signedUnit = [&] { return 2.0f * unit(rng) - 1.0f; };
  std::vector<Mover> movers(count);
  Material ground;
  ground.collision_distance = 0.5f;
  EXPECT_EQ(Body::create(&fields().slab.view, ground, &movers[0].body), Status::kOk);
  movers[0].position = {0.0f, 0.0f, -30.0f};
  movers[0].scale = 10.0f;
  for (std::size_t b = 1; b < count; ++b) {
    Mover& m = movers[b];
    const View* view = unit(rng) < 0.5f ? &fields().sphere.view : &fields().box.view;
    EXPECT_EQ(Body::create(view, randomMaterial(rng), &m.body), Status::kOk);
    m.position = {100.0f * signedUnit(), 100.0f * signedUnit(), 40.0f * unit(rng)};
    m.scale = 0.1f + 1.4f * unit(rng);
    m.axis = normalizeOrZero({signedUnit(), signedUnit(), signedUnit() + 0.01f});
    m.angle = 6.0f * unit(rng);
    const int kind = int(b % 3);
    if (kind >= 1) m.velocity = Vec3f{signedUnit(), signedUnit(), signedUnit()} * 30.0f;
    if (kind == 2) m.spin = 3.0f * signedUnit();
  }
  for (Mover& m : movers)
    m.place();
  return movers;
}

std::vector<Body> bodiesOf(const std::vector<Mover>& movers) {
  std::vector<Body> out;
  for (const Mover& m : movers)
    out.push_back(m.body);
  return out;
}

// Most particles close to a random body, some anywhere in the scene, some far outside it or very
// fast, and a few with non-finite positions or velocities.
Particles randomParticles(const std::vector<Mover>& movers, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto signedUnit = [&] { return 2.0f * unit(rng) - 1.0f; };
  Particles p;
  while (p.size() < count) {
    const float pick = unit(rng);
    const Vec3f dir = Vec3f{signedUnit(), signedUnit(), signedUnit()};
    Vec3f position;
    if (pick < 0.7f) {
      const Mover& m = movers[std::size_t(unit(rng) * float(movers.size())) % movers.size()];
      position = m.position + dir * (14.0f * m.scale);
    } else if (pick < 0.9f) {
      position = {110.0f * signedUnit(), 110.0f * signedUnit(), 60.0f * unit(rng) - 5.0f};
    } else {
      position = dir * 5000.0f;
    }
    const float speed = unit(rng) < 0.1f ? 600.0f : 60.0f * unit(rng);
    p.add(position, normalizeOrZero({signedUnit(), signedUnit(), signedUnit()}) * speed);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  p.add({nan, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
  p.add({1.0f, 2.0f, 3.0f}, {nan, 0.0f, 0.0f});
  p.add({1.0f, 2.0f, 3.0f}, {0.0f, inf, 0.0f});
  p.add({-inf, 2.0f, 3.0f}, {0.0f, 1.0f, 0.0f});
  return p;
}

// Bit for bit, NaN included.
template <class T> bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expectSame(const Particles& a, const Particles& b, int step) {
  EXPECT_TRUE(sameBits(a.px, b.px) && sameBits(a.py, b.py) && sameBits(a.pz, b.pz)) << "positions, step " << step;
  EXPECT_TRUE(sameBits(a.vx, b.vx) && sameBits(a.vy, b.vy) && sameBits(a.vz, b.vz)) << "velocities, step " << step;
  EXPECT_TRUE(sameBits(a.contact, b.contact)) << "contacts, step " << step;
  EXPECT_TRUE(sameBits(a.body, b.body)) << "bodies, step " << step;
}

class SameResults : public ::testing::TestWithParam<int> {};

// Every step: gravity, then one step of each copy, one through a freshly rebuilt index; then the
// bodies move on to where their velocities took them, as an engine would move them.
TEST_P(SameResults, WithAndWithoutTheIndexBitForBit) {
  const std::size_t body_count = std::size_t(GetParam());
  std::vector<Mover> movers = randomScene(body_count, 7 + std::uint32_t(body_count));
  Particles plain = randomParticles(movers, 4000, 11 + std::uint32_t(body_count));
  Particles indexed = plain;
  BodyIndex index;
  long contacts = 0;
  for (int step = 0; step < 8; ++step) {
    const std::vector<Body> bodies = bodiesOf(movers);
    ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
    ASSERT_EQ(applyGravity(plain.span(), {0, 0, -9.81f}, kDt), Status::kOk);
    ASSERT_EQ(applyGravity(indexed.span(), {0, 0, -9.81f}, kDt), Status::kOk);
    ASSERT_EQ(stepParticles(plain.span(), kDt, bodies.data(), bodies.size()), Status::kOk);
    Diagnostic diag;
    ASSERT_EQ(stepParticles(indexed.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kOk)
        << diag.message;
    expectSame(plain, indexed, step);
    for (std::uint8_t c : plain.contact)
      contacts += c;
    for (Mover& m : movers)
      m.advance(kDt);
  }
  // The particles met the bodies often enough for the comparison to say something.
  EXPECT_GT(contacts, 1000);
}

// 1 body: the ground alone; 70: more bodies than the step keeps motions for and samples of (64, 8).
INSTANTIATE_TEST_SUITE_P(BodyCounts, SameResults, ::testing::Values(1, 9, 70, 300));

// Steps a copy of `start` with every body and another through `index`, expects them bit for bit the
// same, and returns how many particles touched a body.
long contactsSteppedBothWays(const std::vector<Body>& bodies, const BodyIndex& index, const Particles& start) {
  Particles plain = start, indexed = start;
  EXPECT_EQ(stepParticles(plain.span(), kDt, bodies.data(), bodies.size()), Status::kOk);
  Diagnostic diag;
  EXPECT_EQ(stepParticles(indexed.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kOk)
      << diag.message;
  expectSame(plain, indexed, 0);
  long contacts = 0;
  for (std::uint8_t c : plain.contact)
    contacts += c;
  return contacts;
}

// The index keeps each body's numbers for the step from its rebuild (pose, motion, box, walk
// constants), but never its material: materials may change between rebuild and step, and the step
// must use them as they are then. Every kind of rule, on bodies listed in the same cells; and again
// after a rebuild with the bodies in place, which keeps the index.
TEST(BodyIndex, MaterialsChangedAfterTheRebuildAreUsed) {
  std::vector<Mover> movers = randomScene(70, 23);
  std::vector<Body> bodies = bodiesOf(movers);
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    Material m;
    m.response = b % 4 == 0 ? Response::kNone : b % 4 == 1 ? Response::kSpring : Response::kImpact;
    m.restitution = 0.1f * float(b % 7);
    m.collision_distance = 0.05f;
    m.drag = b % 2 == 0 ? 3.0f : 0.0f, m.contact_distance = 0.3f;
    m.flow_in = b % 3 == 0 ? 2.0f : 0.0f, m.flow_distance = 0.3f;
    m.swept = b % 5 == 0;
    ASSERT_EQ(bodies[b].setMaterial(m), Status::kOk);
  }
  const Particles start = randomParticles(movers, 4000, 29);
  EXPECT_GT(contactsSteppedBothWays(bodies, index, start), 100);
  // Rebuilt with the bodies in place, the index is kept and finds which bodies share a material again.
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  EXPECT_GT(contactsSteppedBothWays(bodies, index, start), 100);
}

// A body with a NaN velocity has no finite motion: the index refuses it, naming it, and so does the
// step without an index (particles_test.cpp), so no move is judged against a box that is not a number.
TEST(BodyIndex, BodiesWithoutAFiniteMotionAreRefused) {
  std::vector<Mover> movers = randomScene(12, 3);
  movers[5].velocity = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f};
  movers[5].place();
  const std::vector<Body> bodies = bodiesOf(movers);
  BodyIndex index;
  Diagnostic diag;
  EXPECT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("body 5"), std::string::npos) << diag.message;
  EXPECT_FALSE(index.built());
  Particles p = randomParticles(movers, 50, 4);
  const Particles before = p;
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), &diag), Status::kInvalidArgument);
  expectSame(before, p, 0);
}

// A town: a ground 220 wide and 100 small boxes on a lattice, at rest.
std::vector<Body> town() {
  std::vector<Body> bodies(101);
  Material m;
  EXPECT_EQ(Body::create(&fields().slab.view, m, &bodies[0]), Status::kOk);
  const float q[4] = {1, 0, 0, 0};
  EXPECT_EQ(bodies[0].setTransform({0.0f, 0.0f, -30.0f}, q, 10.0f), Status::kOk);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(Body::create(&fields().box.view, m, &bodies[std::size_t(i) + 1]), Status::kOk);
    const Vec3f at{20.0f * float(i % 10) - 90.0f, 20.0f * float(i / 10) - 90.0f, 3.5f};
    EXPECT_EQ(bodies[std::size_t(i) + 1].setTransform(at, q, 0.5f), Status::kOk);
  }
  return bodies;
}

bool overlaps(const Body& b, Vec3f lo, Vec3f hi) {
  const Vec3f blo = b.boundsMin(), bhi = b.boundsMax();
  return !(hi.x < blo.x || hi.y < blo.y || hi.z < blo.z || lo.x > bhi.x || lo.y > bhi.y || lo.z > bhi.z);
}

// Bodies of very different sizes: a point lists the ground and the box it is in; a point far outside
// lists nothing; any box lists exactly the bodies it overlaps, in increasing order.
TEST(BodyIndex, ListsFewBodiesAndEveryOverlappingOne) {
  const std::vector<Body> bodies = town();
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  std::uint32_t dims[3];
  index.cellDims(dims);
  EXPECT_LE(std::size_t(dims[0]) * dims[1] * dims[2], 8 * bodies.size()) << dims[0] << " " << dims[1] << " " << dims[2];
  std::uint32_t near[128];
  const Vec3f in_box_55{20.0f * 5 - 90.0f + 1.0f, 20.0f * 5 - 90.0f, 4.0f};
  const std::size_t found = index.bodiesNear(in_box_55, in_box_55, near, 128);
  ASSERT_EQ(found, 2u);
  EXPECT_EQ(near[0], 0u);
  EXPECT_NE(std::find(near, near + found, 56u), near + found);
  EXPECT_EQ(index.bodiesNear({5e3f, 0, 0}, {5e3f, 0, 0}, near, 128), 0u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(index.bodiesNear({nan, nan, nan}, {nan, nan, nan}, nullptr, 0), bodies.size());

  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coordinate(-130.0f, 130.0f), size(0.0f, 15.0f);
  for (int query = 0; query < 2000; ++query) {
    const Vec3f lo{coordinate(rng), coordinate(rng), coordinate(rng) * 0.3f};
    const Vec3f hi = lo + Vec3f{size(rng), size(rng), size(rng)};
    const std::size_t n = index.bodiesNear(lo, hi, near, 128);
    ASSERT_LE(n, 128u);
    for (std::size_t k = 1; k < n; ++k)
      ASSERT_LT(near[k - 1], near[k]);
    for (std::uint32_t b = 0; b < bodies.size(); ++b) // at rest: the grown boxes are the bounds
      ASSERT_EQ(std::find(near, near + n, b) != near + n, overlaps(bodies[b], lo, hi)) << "query " << query;
  }
}

// The bodies rebuild(...) lists at the point p, as a sorted vector.
std::vector<std::uint32_t> listedAt(const BodyIndex& index, Vec3f p) {
  std::uint32_t near[128];
  const std::size_t n = index.bodiesNear(p, p, near, 128);
  return std::vector<std::uint32_t>(near, near + std::min<std::size_t>(n, 128));
}

// A rebuild for bodies that have not changed since the last one gives the same index without building
// it again (a city's buildings at rest, frame after frame); whatever the build reads changing rebuilds
// it: a body's place, its velocity, dt, the number of bodies, a body made invalid.
TEST(BodyIndex, ARebuildSeesEveryChange) {
  std::vector<Body> bodies = town();
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  const Vec3f in_box_55{20.0f * 5 - 90.0f + 1.0f, 20.0f * 5 - 90.0f, 4.0f};
  const std::vector<std::uint32_t> ground_and_55{0u, 56u};
  ASSERT_EQ(listedAt(index, in_box_55), ground_and_55);
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk); // nothing changed
  EXPECT_TRUE(index.built());
  EXPECT_EQ(listedAt(index, in_box_55), ground_and_55);

  // Moved beyond the ground's box.
  const float q[4] = {1, 0, 0, 0};
  const Vec3f away{400.0f, 0.0f, 0.0f};
  ASSERT_EQ(bodies[56].setTransform(away, q, 0.5f), Status::kOk);
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  EXPECT_EQ(listedAt(index, in_box_55), std::vector<std::uint32_t>{0u});
  EXPECT_EQ(listedAt(index, away), std::vector<std::uint32_t>{56u});

  // A velocity grows the box by how far the body moves in dt (10 units here), and a longer dt more.
  const Vec3f beyond_56{away.x, bodies[56].boundsMax().y + 8.0f, away.z};
  EXPECT_TRUE(listedAt(index, beyond_56).empty());
  bodies[56].setVelocity({0.0f, 600.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  EXPECT_EQ(listedAt(index, beyond_56), std::vector<std::uint32_t>{56u});
  const Vec3f farther{away.x, bodies[56].boundsMax().y + 15.0f, away.z};
  EXPECT_TRUE(listedAt(index, farther).empty());
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), 2.0f * kDt), Status::kOk);
  EXPECT_EQ(index.dt(), 2.0f * kDt);
  EXPECT_EQ(listedAt(index, farther), std::vector<std::uint32_t>{56u});

  // Fewer bodies: the last one leaves the index.
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size() - 1, 2.0f * kDt), Status::kOk);
  EXPECT_EQ(index.bodyCount(), bodies.size() - 1);
  const Vec3f in_box_99 = bodies[100].translation();
  EXPECT_EQ(listedAt(index, in_box_99), std::vector<std::uint32_t>{0u});

  // A failed rebuild empties the index, and the next one builds it whole.
  EXPECT_EQ(index.rebuild(bodies.data(), bodies.size(), -1.0f), Status::kInvalidArgument);
  EXPECT_FALSE(index.built());
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), 2.0f * kDt), Status::kOk);
  EXPECT_EQ(listedAt(index, in_box_99), (std::vector<std::uint32_t>{0u, 100u}));

  // A body replaced by an empty one is refused, named, as in a first build.
  bodies[3] = Body();
  Diagnostic diag;
  EXPECT_EQ(index.rebuild(bodies.data(), bodies.size(), 2.0f * kDt, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("body 3"), std::string::npos) << diag.message;
  EXPECT_FALSE(index.built());
}

// One building-sized body next to one a million times larger: the grid stays small and correct.
TEST(BodyIndex, ExtremeSizesKeepTheGridSmall) {
  std::vector<Body> bodies = town();
  const float q[4] = {1, 0, 0, 0};
  ASSERT_EQ(bodies[1].setTransform({0, 0, 0}, q, 1e5f), Status::kOk);
  ASSERT_EQ(bodies[2].setTransform({3, 3, 3}, q, 0.01f), Status::kOk);
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  std::uint32_t dims[3];
  index.cellDims(dims);
  EXPECT_LE(std::size_t(dims[0]) * dims[1] * dims[2], 8 * bodies.size() + 64);
  std::uint32_t near[128];
  const std::size_t n = index.bodiesNear({3, 3, 3}, {3, 3, 3}, near, 128);
  EXPECT_NE(std::find(near, near + std::min<std::size_t>(n, 128), 1u), near + std::min<std::size_t>(n, 128));
  EXPECT_NE(std::find(near, near + std::min<std::size_t>(n, 128), 2u), near + std::min<std::size_t>(n, 128));
}

// An index that no longer matches the bodies is refused before any particle moves.
TEST(BodyIndex, StaleOrMismatchedIndexIsRefused) {
  std::vector<Body> bodies = town();
  Particles p;
  p.add({0.0f, 0.0f, 20.0f}, {0.0f, 0.0f, -5.0f});
  BodyIndex index;
  Diagnostic diag;
  EXPECT_FALSE(index.built());
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("not built"), std::string::npos) << diag.message;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  EXPECT_TRUE(index.built());
  EXPECT_EQ(index.bodyCount(), bodies.size());
  EXPECT_EQ(index.dt(), kDt);
  EXPECT_EQ(stepParticles(p.span(), 0.5f * kDt, bodies.data(), bodies.size(), index, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("dt"), std::string::npos) << diag.message;
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size() - 1, index, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("built for 101 bodies"), std::string::npos) << diag.message;
  bodies[42].setVelocity({0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("body 42"), std::string::npos) << diag.message;
  EXPECT_EQ(p.pz[0], 20.0f);
  EXPECT_EQ(p.vz[0], -5.0f);
  // Materials are not the index's business; a moved index still serves.
  Material sticky;
  sticky.drag = 1.0f;
  bodies[42].setVelocity({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f});
  ASSERT_EQ(bodies[42].setMaterial(sticky), Status::kOk);
  BodyIndex moved = std::move(index);
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), moved, &diag), Status::kOk) << diag.message;
  // A failed rebuild leaves the index empty.
  EXPECT_EQ(moved.rebuild(bodies.data(), bodies.size(), -1.0f), Status::kInvalidArgument);
  EXPECT_FALSE(moved.built());
  EXPECT_EQ(moved.rebuild(nullptr, 3, kDt), Status::kInvalidArgument);
  const Body invalid;
  EXPECT_EQ(moved.rebuild(&invalid, 1, kDt), Status::kInvalidArgument);
  EXPECT_EQ(moved.rebuild(nullptr, 0, kDt), Status::kOk); // no bodies: a valid, empty index
  EXPECT_EQ(stepParticles(p.span(), kDt, nullptr, 0, moved), Status::kOk);
}

// A View opened again in place on another file changes the field under its bodies: the index, which
// keeps what it took from the fields (the encoding picks the kernels' lookup), is stale. Stepped as it
// was, a dense lookup ran on a bricked view and crashed.
TEST(BodyIndex, AViewOpenedAgainOnAnotherFileMakesTheIndexStale) {
  const format::DenseField sphere =
      analytic::sampleField(analytic::cubeGrid({-12, -12, -12}, 1.0f, 24, 3.8661f), analytic::sphereField({}, 8.0f));
  const format::EncodeResult dense = format::encodeDense(sphere, ""), bricked = format::encodeBricked(sphere, {}, "");
  ASSERT_TRUE(dense.ok() && bricked.ok());
  View view;
  ASSERT_EQ(View::open(dense.bytes.data(), dense.bytes.size(), &view), Status::kOk);
  std::vector<Body> bodies(9); // more than the kernels take without an index
  const float q[4] = {1, 0, 0, 0};
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    ASSERT_EQ(Body::create(&view, Material{}, &bodies[b]), Status::kOk);
    ASSERT_EQ(bodies[b].setTransform({30.0f * float(b), 0.0f, 0.0f}, q, 1.0f), Status::kOk);
  }
  BodyIndex index;
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  Particles p;
  for (int i = 0; i < 64; ++i) // beside body 0's surface, moving onto it
    p.add({-9.0f - 0.01f * float(i), 0.1f * float(i % 8), 0.0f}, {30.0f, 0.0f, 0.0f});
  Particles before = p;
  ASSERT_EQ(View::open(bricked.bytes.data(), bricked.bytes.size(), &view), Status::kOk);
  Diagnostic diag;
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kInvalidArgument);
  EXPECT_NE(std::string(diag.message).find("body 0"), std::string::npos) << diag.message;
  EXPECT_EQ(p.px, before.px);
  // Rebuilt, the index serves the new file, as stepping without it does.
  ASSERT_EQ(index.rebuild(bodies.data(), bodies.size(), kDt), Status::kOk);
  EXPECT_EQ(stepParticles(p.span(), kDt, bodies.data(), bodies.size(), index, &diag), Status::kOk) << diag.message;
  EXPECT_EQ(stepParticles(before.span(), kDt, bodies.data(), bodies.size(), &diag), Status::kOk) << diag.message;
  EXPECT_EQ(p.px, before.px);
  EXPECT_EQ(p.vx, before.vx);
}

} // namespace
} // namespace dng
