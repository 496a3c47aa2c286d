// stepParticles: responses per body (paper §3.3-3.6), then a move that cannot cross a surface.
//
// The responses happen in the world frame: only the particle position goes into a body's frame for
// the field lookup, and the distance (times the body's scale) and the normal (rotated) come back out.
// The move is judged in each body's own frame, from the body's pose at the start of the step to its
// pose at the end (pose.h), by the conservative walk (walk.h). A blocked particle stops where the walk
// proved the way clear, bounces off the blocking plane with the body's restitution, and slides the
// rest of its step along that plane when the straight path to there is clear too.
#include "broadphase.h"
#include "diagnostic.h"
#include "dng/body_index.h"
#include "dng/particles.h"
#include "dng/responses.h"
#include "fast_math.h"
#include "pose.h"
#include "step_batch.h"
#include "strided.h"
#include "view_internals.h"
#include "walk.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace dng {

namespace {

int walkSamples(const Body& body) { return walkSamples(body.material()); } // step_batch.h

// +0 in every component, bit for bit (a body at rest: its lanes may take splatted zeros for it).
bool bitsZero(Vec3f v) {
  const float zero[3] = {0.0f, 0.0f, 0.0f};
  return std::memcmp(&v, zero, sizeof zero) == 0;
}

// Samples kept from the responses for the walk: those of the first bodies that hold the particle in
// their boxes (rarely more than two or three); more bodies sample twice.
constexpr std::size_t kKeptSamples = 8;

struct ParticleState {
  Vec3f position;
  Vec3f velocity;
};

ParticleState load(const ParticleSpan& s, std::size_t n) {
  return {{strided(s.position_x, s.position_stride, n), strided(s.position_y, s.position_stride, n),
           strided(s.position_z, s.position_stride, n)},
          {strided(s.velocity_x, s.velocity_stride, n), strided(s.velocity_y, s.velocity_stride, n),
           strided(s.velocity_z, s.velocity_stride, n)}};
}

void store(const ParticleSpan& s, std::size_t n, const ParticleState& p) {
  strided(s.position_x, s.position_stride, n) = p.position.x;
  strided(s.position_y, s.position_stride, n) = p.position.y;
  strided(s.position_z, s.position_stride, n) = p.position.z;
  strided(s.velocity_x, s.velocity_stride, n) = p.velocity.x;
  strided(s.velocity_y, s.velocity_stride, n) = p.velocity.y;
  strided(s.velocity_z, s.velocity_stride, n) = p.velocity.z;
}

bool insideBounds(const Body& b, Vec3f p) {
  const Vec3f lo = b.boundsMin(), hi = b.boundsMax();
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// Whether the world segment a -> b can touch the body's world box in either of its poses. The box of
// the swept segment against the box grown by how far the body moves its farthest corner.
bool segmentNearBounds(const Body& body, Vec3f a, Vec3f b, float body_travel) {
  const Vec3f lo = body.boundsMin(), hi = body.boundsMax();
  for (int axis = 0; axis < 3; ++axis) {
    const float s_lo = minOf(component(a, axis), component(b, axis));
    const float s_hi = maxOf(component(a, axis), component(b, axis));
    if (s_hi < component(lo, axis) - body_travel || s_lo > component(hi, axis) + body_travel) return false;
  }
  return true;
}

// Each body's motion in the step (broadphase.h): all of them from the index when there is one;
// else the first kStored are computed once per call, the rest (large scenes) when a particle comes
// near them, so a step never allocates.
class BodyMotions {
public:
  BodyMotions(const Body* bodies, std::size_t count, float dt, const BodyMotion* indexed)
      : bodies_(bodies), dt_(dt), indexed_(indexed) {
    for (std::size_t b = 0; indexed == nullptr && b < count && b < kStored; ++b)
      stored_[b] = motionOf(bodies[b], dt);
  }
  /// Body b's motion: an indexed or stored one, or computed into *scratch.
  const BodyMotion& get(std::size_t b, BodyMotion* scratch) const {
    if (indexed_ != nullptr) return indexed_[b];
    if (b < kStored) return stored_[b];
    *scratch = motionOf(bodies_[b], dt_);
    return *scratch;
  }

private:
  static constexpr std::size_t kStored = 64;
  const Body* bodies_;
  float dt_;
  const BodyMotion* indexed_;
  BodyMotion stored_[kStored];
};

// Which body touched the particle, if any: the nearest of those that acted.
struct Touch {
  std::int32_t body = -1;
  float distance = std::numeric_limits<float>::infinity();
  void record(std::size_t index, float d) {
    if (d < distance) {
      distance = d;
      body = std::int32_t(index);
    }
  }
};

// The response samples, kept for the walk's first sample (the walk starts where the response sampled,
// so it would read the same answer again), by body index: in a large scene the particle's bodies may
// have any index. Raw storage: a particle far from every body keeps none, and should not pay for
// constructing them.
class KeptSamples {
public:
  void keep(std::size_t body, const Sample& s) {
    if (count_ == kKeptSamples) return;
    body_[count_] = body;
    std::memcpy(storage_ + count_ * sizeof(Sample), &s, sizeof(Sample));
    ++count_;
  }
  bool find(std::size_t body, Sample* out) const {
    for (std::size_t k = 0; k < count_; ++k) {
      if (body_[k] != body) continue;
      std::memcpy(out, storage_ + k * sizeof(Sample), sizeof(Sample));
      return true;
    }
    return false;
  }

private:
  alignas(Sample) unsigned char storage_[kKeptSamples * sizeof(Sample)];
  std::size_t body_[kKeptSamples];
  std::size_t count_ = 0;
};

// Samples one body at the particle and applies its material to the velocity relative to its surface.
void respondToBody(const Body& body, std::size_t index, float dt, ParticleState* io, Touch* io_touch,
                   KeptSamples* io_kept) {
  if (!insideBounds(body, io->position)) return;
  // The walk keeps the plane; the rules read the shading normal (the same unless the file has SHAD).
  Vec3f shading;
  const Sample s = ViewInternals::planeSample(*body.field(), body.toLocal(io->position), &shading);
  io_kept->keep(index, s);
  if (s.status != SampleStatus::kInBand) return;
  const Contact contact{s.distance * body.scale(), body.rotateToWorld(shading)};
  const Vec3f surface = body.surfaceVelocity(io->position);
  Vec3f relative = io->velocity - surface;
  if (respond(body.material(), contact, body.field()->grid().band * body.scale(), dt, &relative)) {
    io->velocity = relative + surface;
    io_touch->record(index, contact.distance);
  }
}

bool collides(const Body& body) { return collides(body.material()); }

// Where the earliest body stopped a straight move, in the world at the end of the step.
struct Stop {
  std::int32_t body = -1;
  float t = 2.0f;
  WalkResult walk;
  Vec3f position; // world, on the blocking body as it stands at the end of the step
  Vec3f local;    // the same point in the body's end-of-step frame, before rounding to world floats
};

// A neighbour bound at the start of the walk through one body, taken by the SIMD kernels.
struct HandedBound {
  std::size_t body = 0;
  const StartBound* bound = nullptr;
};

// Which bodies firstStop walks through: every colliding one, or the moving ones only (a travel over the
// step above zero); either way not `skip`.
struct Through {
  std::int32_t skip = -1;
  bool moving_only = false;
};

// Walks the world move start -> end through the colliding bodies near it that `through` names, in each
// body's frame.
Stop firstStop(const Body* bodies, const NearBodies& near, const BodyMotions& motions, Vec3f start, Vec3f end,
               const KeptSamples* kept, HandedBound handed = {}, Through through = {}) {
  Stop first;
  // The box segmentNearBounds tests, so the broadphase lists every body the test can pass (the lanes
  // compute the same box: span_lanes.h).
  const Vec3f lo{minOf(start.x, end.x), minOf(start.y, end.y), minOf(start.z, end.z)};
  const Vec3f hi{maxOf(start.x, end.x), maxOf(start.y, end.y), maxOf(start.z, end.z)};
  near.forEach(lo, hi, BodyBox::kGrown, [&](std::size_t b) {
    const Body& body = bodies[b];
    if (!collides(body) || std::int32_t(b) == through.skip) return;
    BodyMotion scratch;
    const BodyMotion& motion = motions.get(b, &scratch);
    if (through.moving_only && !(motion.travel > 0.0f)) return;
    if (!segmentNearBounds(body, start, end, motion.travel)) return;
    const Vec3f a = body.toLocal(start);
    const Pose& end_pose = motion.end;
    const Vec3f delta = end_pose.toLocal(end) - a;
    const float margin = kMarginVoxels * body.field()->grid().voxel_size;
    const int samples = walkSamples(body);
    Sample kept_sample;
    const bool reuse = kept != nullptr && kept->find(b, &kept_sample);
    const WalkResult walk = walkSegment(*body.field(), a, delta, reuse ? &kept_sample : nullptr, margin, samples,
                                        handed.body == b ? handed.bound : nullptr);
    if (walk.stop == WalkStop::kClear || walk.t >= first.t) return;
    const Vec3f local = a + delta * walk.t;
    first = {std::int32_t(b), walk.t, walk, end_pose.toWorld(local), local};
  });
  return first;
}

// Bounces the velocity off the stop: the normal part reflects with the body's restitution (kPlane),
// or the whole relative velocity turns back (kReverse); a stall keeps it.
Vec3f bounce(const Body& body, const Pose& end_pose, const Stop& stop, Vec3f velocity) {
  if (stop.walk.stop == WalkStop::kStall) return velocity;
  const Vec3f surface = body.surfaceVelocity(stop.position);
  Vec3f relative = velocity - surface;
  const float restitution = body.material().restitution;
  if (stop.walk.stop == WalkStop::kReverse) return surface - relative * restitution;
  const Vec3f n = end_pose.rotateToWorld(stop.walk.normal);
  const float vn = dot(relative, n);
  if (vn < 0.0f) relative = relative - n * ((1.0f + restitution) * vn);
  return relative + surface;
}

// Where a plane stopped the move from `from` to `to`, the rest of the move without its part into
// the plane (a particle's slide along the surface that stopped it).
Vec3f slideAlong(const BodyMotions& motions, Vec3f from, Vec3f to, const Stop& stop) {
  BodyMotion scratch;
  const Vec3f n = motions.get(std::size_t(stop.body), &scratch).end.rotateToWorld(stop.walk.normal);
  const Vec3f rest = (to - from) * (1.0f - stop.t);
  return stop.position + rest - n * minOf(dot(rest, n), 0.0f);
}

// Another body may arrive where a stop left the particle: the stop is where the particle is at the
// end of the step, but each body's walk only saw the particle's own move, and a body that keeps moving
// after the stop (a ball rolling along the ground that stopped a particle ahead of it) would end the
// step over it. So the move to the stop is walked again through the other moving bodies. One that
// blocks it pushes the particle to its own surface and bounces it as a stop does; the push, from the
// stop to there, must be clear of every other body, or slide along the plane that blocks it. A
// particle crushed between two bodies closing in has no place outside both: it stays with the pusher.
void resolvePinch(const Body* bodies, const NearBodies& near, const BodyMotions& motions, Vec3f start,
                  std::int32_t stopped_by, ParticleState* io, Touch* io_touch) {
  // A body at rest arrives nowhere: a static scene pays a look at each nearby body's travel here.
  const Stop pusher = firstStop(bodies, near, motions, start, io->position, nullptr, {}, {stopped_by, true});
  if (pusher.body < 0) return;
  BodyMotion scratch;
  const Pose& pose = motions.get(std::size_t(pusher.body), &scratch).end;
  io->velocity = bounce(bodies[pusher.body], pose, pusher, io->velocity);
  io_touch->record(std::size_t(pusher.body), 0.0f);
  const Vec3f from = io->position;
  io->position = pusher.position;
  const Stop blocked = firstStop(bodies, near, motions, from, pusher.position, nullptr, {}, {pusher.body});
  if (blocked.body < 0 || blocked.walk.stop != WalkStop::kPlane) return;
  const Vec3f slid = slideAlong(motions, from, pusher.position, blocked);
  if (firstStop(bodies, near, motions, from, slid, nullptr, {}, {pusher.body}).body < 0) io->position = slid;
}

// The particle's move from `start` to `end` that `stop` ends: it stays there, bounces off the stop
// and, off a plane, slides along it where no body is in the way; where another body arrives at the
// stop, it is pushed out of that body's way (resolvePinch).
void settle(const Body* bodies, const NearBodies& near, const BodyMotions& motions, Vec3f start, Vec3f end,
            const Stop& stop, ParticleState* io, Touch* io_touch) {
  const Body& body = bodies[stop.body];
  BodyMotion scratch;
  const Pose& pose = motions.get(std::size_t(stop.body), &scratch).end;
  io->position = stop.position;
  // Far from the origin world floats are coarse (a quarter of a voxel apart at 4 * 10^6 with unit
  // voxels): the stop, found in the body's frame, may round to a point past the walk's margin. Where
  // the rounding moved it by more than a quarter of the margin, keep it only if the move to it is clear
  // on the floats the particle will hold; else the particle stays at its start. Nearer the origin the
  // rounding is far smaller and this never runs.
  const float margin = kMarginVoxels * body.field()->grid().voxel_size;
  if (length(pose.toLocal(stop.position) - stop.local) > 0.25f * margin &&
      firstStop(bodies, near, motions, start, stop.position, nullptr).body >= 0)
    io->position = start;
  io->velocity = bounce(body, pose, stop, io->velocity);
  io_touch->record(std::size_t(stop.body), 0.0f);
  if (stop.walk.stop == WalkStop::kPlane) {
    // Slide, kept only when the straight path from the start is clear too (a particle's step is the
    // segment between its two positions).
    const Vec3f slid = slideAlong(motions, start, end, stop);
    if (firstStop(bodies, near, motions, start, slid, nullptr).body < 0) {
      io->position = slid;
      return; // clear through every body
    }
  }
  resolvePinch(bodies, near, motions, start, stop.body, io, io_touch);
}

// Moves the particle by v dt without crossing any colliding body.
void move(const Body* bodies, const NearBodies& near, const BodyMotions& motions, float dt, const KeptSamples& kept,
          ParticleState* io, Touch* io_touch, HandedBound handed = {}) {
  const Vec3f start = io->position;
  const Vec3f end = start + io->velocity * dt;
  const Stop stop = firstStop(bodies, near, motions, start, end, &kept, handed);
  if (stop.body < 0) {
    io->position = end;
    return;
  }
  settle(bodies, near, motions, start, end, stop, io, io_touch);
}

// `indexed`: the call goes through an index, whose rebuild checked the bodies' motions and whose
// matches() finds them unchanged; per call, that saves a pose turned by each body's spin.
Status checkStep(const ParticleSpan& s, float dt, const Body* bodies, std::size_t body_count, bool indexed,
                 Diagnostic* diag) {
  if (!(dt > 0.0f) || !std::isfinite(dt))
    return writeDiagnostic(diag, Status::kInvalidArgument, "dt must be finite and > 0, got %g", double(dt));
  if (body_count > 0 && bodies == nullptr)
    return writeDiagnostic(diag, Status::kInvalidArgument, "bodies is null but body_count is %zu", body_count);
  for (std::size_t b = 0; b < body_count; ++b) {
    if (!bodies[b].valid()) return writeDiagnostic(diag, Status::kInvalidArgument, "body %zu is not valid", b);
    if (!walkable(*bodies[b].field())) // Body::create refuses such fields; its View may have been opened again
      return writeDiagnostic(diag, Status::kInvalidArgument, "body %zu: its field's band is too thin to step through",
                             b);
    const Status motion = indexed ? Status::kOk : checkMotion(bodies[b], b, dt, diag);
    if (motion != Status::kOk) return motion;
  }
  if (s.count == 0) return Status::kOk;
  if (!s.position_x || !s.position_y || !s.position_z || !s.velocity_x || !s.velocity_y || !s.velocity_z)
    return writeDiagnostic(diag, Status::kInvalidArgument, "particle position and velocity pointers must be set");
  if (!validStride(s.position_stride) || !validStride(s.velocity_stride))
    return writeDiagnostic(diag, Status::kInvalidArgument,
                           "particle strides must be whole floats, at least 4 bytes (got %zu and %zu)",
                           s.position_stride, s.velocity_stride);
  if (!spanFits(s.count, s.position_stride) || !spanFits(s.count, s.velocity_stride))
    return writeDiagnostic(diag, Status::kInvalidArgument,
                           "%zu particles at strides of %zu and %zu bytes do not fit in memory", s.count,
                           s.position_stride, s.velocity_stride);
  return Status::kOk;
}

// Everything one particle's step needs: the scalar path, the reference for the SIMD kernels.
struct ScalarStep {
  const ParticleSpan* particles;
  float dt;
  const Body* bodies;
  const NearBodies* near;
  const BodyMotions* motions;
};

// A particle's step written: its state and touched body.
void storeParticle(const ScalarStep& step, std::size_t n, const ParticleState& state, const Touch& touch) {
  store(*step.particles, n, state);
  writeTouch(*step.particles, n, touch.body);
}

// The end of a particle's step: its move after the responses, then its state and touched body written.
void moveAndStore(const ScalarStep& step, std::size_t n, const KeptSamples& kept, ParticleState state, Touch touch,
                  HandedBound handed = {}) {
  move(step.bodies, *step.near, *step.motions, step.dt, kept, &state, &touch, handed);
  storeParticle(step, n, state, touch);
}

void stepOne(const void* context, std::size_t n) {
  const ScalarStep& step = *static_cast<const ScalarStep*>(context);
  ParticleState state = load(*step.particles, n);
  Touch touch;
  KeptSamples kept;
  step.near->forEach(state.position, state.position, BodyBox::kBounds,
                     [&](std::size_t b) { respondToBody(step.bodies[b], b, step.dt, &state, &touch, &kept); });
  moveAndStore(step, n, kept, state, touch);
}

// stepOne's move alone, after the lanes' responses (StepBatch::scalar_move). Without the responses'
// samples the walks sample their starts themselves: the same numbers.
void moveOne(const void* context, std::size_t n, Vec3f velocity, std::int32_t touch_body, float touch_distance,
             const StartBound* start_bound, std::size_t bound_body) {
  const ScalarStep& step = *static_cast<const ScalarStep*>(context);
  ParticleState state = load(*step.particles, n);
  state.velocity = velocity;
  moveAndStore(step, n, KeptSamples(), state, Touch{touch_body, touch_distance}, {bound_body, start_bound});
}

// moveOne for a particle whose walk through body `b`, the only one its move meets, the lanes found
// blocked at its start (walkSegment's kReverse at t = 0): the stop that walk returns, settled as move
// settles it, without walking again.
void blockOne(const void* context, std::size_t n, Vec3f velocity, std::int32_t touch_body, float touch_distance,
              std::size_t b) {
  const ScalarStep& step = *static_cast<const ScalarStep*>(context);
  ParticleState state = load(*step.particles, n);
  state.velocity = velocity;
  Touch touch{touch_body, touch_distance};
  const Vec3f start = state.position;
  const Vec3f end = start + state.velocity * step.dt;
  // The numbers firstStop gives this walk's stop.
  const Body& body = step.bodies[b];
  BodyMotion scratch;
  const Pose& end_pose = step.motions->get(b, &scratch).end;
  const Vec3f a = body.toLocal(start);
  const Vec3f delta = end_pose.toLocal(end) - a;
  const WalkResult walk{WalkStop::kReverse, 0.0f, delta * (-1.0f / length(delta))};
  const Vec3f local = a + delta * walk.t;
  const Stop stop{std::int32_t(b), walk.t, walk, end_pose.toWorld(local), local};
  settle(step.bodies, *step.near, *step.motions, start, end, stop, &state, &touch);
  storeParticle(step, n, state, touch);
}

// The batch kernels take up to kMaxBatchBodies bodies, or any number through an index, whose fields
// they can index; null otherwise.
const BatchKernels* kernelsFor(const Body* bodies, std::size_t body_count, bool indexed) {
  const BatchKernels* kernels = activeBatchKernels();
  if (kernels == nullptr || (body_count > kMaxBatchBodies && !indexed)) return nullptr;
  for (std::size_t b = 0; b < body_count; ++b) {
    if (!batchIndexable(*bodies[b].field())) return nullptr;
  }
  return kernels;
}

// The index's grid as the kernels read it.
IndexGrid gridOf(const BodyIndex::Impl& index) {
  IndexGrid g;
  g.boxes = index.boxes.data();
  g.cell_start = index.cell_start.data();
  g.cell_bodies = index.cell_bodies.data();
  g.cell_boxes = index.cell_boxes.data();
  g.everywhere = index.everywhere.data();
  g.everywhere_count = index.everywhere.size();
  g.inv_cell = index.inv_cell;
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = index.origin[a];
    g.last_cell[a] = index.last_cell[a];
    g.dims[a] = index.dims[a];
  }
  g.scene_lo = index.scene_lo;
  g.scene_hi = index.scene_hi;
  return g;
}

// The step in lanes. With at most kMaxBatchBodies bodies the kernels test every body, prepared once:
// with an index that is what it would list, and the results are the same either way. With more, the
// chunks of lanes find theirs through the index (near_lanes.h).
void stepInLanes(const BatchKernels& kernels, const ScalarStep& scalar, std::size_t body_count,
                 const BodyIndex::Impl* index) {
  StepBatch batch;
  batch.particles = scalar.particles;
  batch.dt = scalar.dt;
  batch.scalar = &stepOne;
  batch.scalar_move = &moveOne;
  batch.scalar_block = &blockOne;
  batch.context = &scalar;
  if (body_count > kMaxBatchBodies) { // kernelsFor took it: there is an index
    const IndexGrid grid = gridOf(*index);
    batch.index = &grid;
    batch.prepared = index->prepared.data();
    batch.bodies = scalar.bodies;
    batch.gatherable = body_count <= std::size_t(INT32_MAX) / (sizeof(StepBody) / sizeof(float));
    batch.kinds = index->kindsHold(scalar.bodies) ? index->kinds.data() : nullptr;
    kernels.step(batch);
    return;
  }
  NearList all;
  all.count = body_count;
  for (std::size_t b = 0; b < body_count; ++b) {
    BodyMotion scratch;
    all.index[b] = all.kept[b] = std::int32_t(b);
    all.storage[b] = prepareStep(scalar.bodies[b], scalar.motions->get(b, &scratch));
    all.body[b] = &all.storage[b];
    all.material[b] = &scalar.bodies[b].material();
  }
  batch.all = &all;
  kernels.step(batch);
}

// The step over checked arguments; `index` (may be null) was built for these bodies and dt.
Status step(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
            const BodyIndex::Impl* index) {
  if (body_count == 0) { // nothing to collide with: integrate
    for (std::size_t n = 0; n < particles.count; ++n) {
      ParticleState state = load(particles, n);
      state.position = state.position + state.velocity * dt;
      store(particles, n, state);
      writeTouch(particles, n, -1);
    }
    return Status::kOk;
  }
  const BodyMotions motions(bodies, body_count, dt, index != nullptr ? index->motions.data() : nullptr);
  const NearBodies near(body_count, index);
  const ScalarStep scalar{&particles, dt, bodies, &near, &motions};
  if (const BatchKernels* kernels = kernelsFor(bodies, body_count, index != nullptr)) {
    stepInLanes(*kernels, scalar, body_count, index);
    return Status::kOk;
  }
  for (std::size_t n = 0; n < particles.count; ++n)
    stepOne(&scalar, n);
  return Status::kOk;
}

} // namespace

StepBody prepareStep(const Body& body, const BodyMotion& motion) {
  const View& field = *body.field();
  StepBody out;
  out.field = &field;
  out.dense = field.grid().encoding == format::Encoding::kDense;
  out.start = currentPose(body);
  out.end = motion.end;
  out.lo = body.boundsMin(), out.hi = body.boundsMax();
  out.linear = body.linearVelocity(), out.angular = body.angularVelocity();
  out.travel = motion.travel;
  out.still = std::memcmp(&out.start, &out.end, sizeof(Pose)) == 0 && bitsZero(out.linear) && bitsZero(out.angular);
  out.band_world = field.grid().band * body.scale();
  out.margin = kMarginVoxels * field.grid().voxel_size;
  out.reach = field.guaranteedReach();
  out.roomy = walkRoomy(field);
  out.proof_level = walkProofLevel(field);
  return out;
}

bool fieldUnchanged(const StepBody& prepared, const Body& body) {
  const View& field = *body.field();
  const GridInfo& g = field.grid();
  // What prepareStep takes from the field: the encoding, and numbers of the band and the voxel size.
  return prepared.field == &field && prepared.dense == (g.encoding == format::Encoding::kDense) &&
         prepared.band_world == g.band * body.scale() && prepared.margin == kMarginVoxels * g.voxel_size &&
         prepared.reach == field.guaranteedReach() && prepared.roomy == walkRoomy(field) &&
         prepared.proof_level == walkProofLevel(field);
}

Status stepParticles(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
                     Diagnostic* out_diag) {
  const Status status = checkStep(particles, dt, bodies, body_count, false, out_diag);
  if (status != Status::kOk) return status;
  return step(particles, dt, bodies, body_count, nullptr);
}

Status stepParticles(const ParticleSpan& particles, float dt, const Body* bodies, std::size_t body_count,
                     const BodyIndex& index, Diagnostic* out_diag) {
  const Status status = checkStep(particles, dt, bodies, body_count, true, out_diag);
  if (status != Status::kOk) return status;
  if (!index.built()) return writeDiagnostic(out_diag, Status::kInvalidArgument, "the body index is not built");
  const BodyIndex::Impl& built = *index.impl_;
  if (std::memcmp(&built.dt, &dt, sizeof dt) != 0)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "the body index was built for dt %g, not %g",
                           double(built.dt), double(dt));
  if (body_count != built.count)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "the body index was built for %zu bodies, not %zu",
                           built.count, body_count);
  std::size_t changed = 0;
  if (!built.matches(bodies, body_count, &changed))
    return writeDiagnostic(out_diag, Status::kInvalidArgument,
                           "the body index is stale: body %zu moved, changed velocity or field since its rebuild",
                           changed);
  return step(particles, dt, bodies, body_count, &built);
}

} // namespace dng
