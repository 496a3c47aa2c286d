// The broadphase (dng/body_index.h): a uniform grid of cells, each listing the bodies whose world box,
// grown by the body's travel in dt, touches it. Why a grid and not a tree: a particle's query is one
// cell (its move rarely leaves the cell), found with three multiplies, and the cell's list is already
// in the body order the step must visit bodies in; a tree would need a traversal and a sort per query.
#include "broadphase.h"
#include "diagnostic.h"
#include "fast_math.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>

namespace dng {

namespace {

// How far any point of the body's box moves in dt: |v| dt plus |w| dt times the box's reach from the
// body's origin.
float bodyTravel(const Body& body, float dt) {
  const Vec3f lo = body.boundsMin() - body.translation(), hi = body.boundsMax() - body.translation();
  const Vec3f far{maxOf(std::fabs(lo.x), std::fabs(hi.x)), maxOf(std::fabs(lo.y), std::fabs(hi.y)),
                  maxOf(std::fabs(lo.z), std::fabs(hi.z))};
  // Without spin the reach does not count: a body scaled past about 1e18 has a reach whose length
  // overflows, and 0 * inf would make a resting body's travel NaN (and its scene unsteppable).
  const float spin = length(body.angularVelocity());
  const float turn = spin == 0.0f ? 0.0f : spin * length(far);
  return (length(body.linearVelocity()) + turn) * dt;
}

// What the index reads of a body besides its field: transform and velocities (its box follows from the
// field and the transform), as the floats' bits, so a NaN velocity still matches itself. Calls
// f(k, bits) for the kStateFloats values; inline, as every step call checks every body.
constexpr std::size_t kStateFloats = 19;
inline std::uint32_t bitsOf(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}
template <class F> inline void forEachState(const Body& body, F&& f) {
  const float* r = body.rotation();
  for (std::size_t k = 0; k < 9; ++k)
    f(k, bitsOf(r[k]));
  const Vec3f vectors[3] = {body.translation(), body.linearVelocity(), body.angularVelocity()};
  for (std::size_t v = 0; v < 3; ++v) {
    f(9 + 3 * v, bitsOf(vectors[v].x));
    f(10 + 3 * v, bitsOf(vectors[v].y));
    f(11 + 3 * v, bitsOf(vectors[v].z));
  }
  f(18, bitsOf(body.scale()));
}

// The grid aims at this many cells per body (fewer bodies per cell costs memory and build time, more
// costs box tests per particle), at most kMaxDim cells along an axis, and gives up resolution when
// bodies would be entered too many times (large bodies overlapping many small cells).
constexpr double kCellsPerBody = 4.0;
constexpr std::uint32_t kMaxDim = 1024;
constexpr double kEntriesPerCellOrBody = 8.0;

// A cubic cell edge giving about kCellsPerBody cells per body over the scene box, counted only over
// the axes the box really extends along: a flat city gets one layer of wide cells, not many thin ones.
double cellEdge(const double extent[3], std::size_t bodies) {
  const double target = kCellsPerBody * double(bodies);
  bool thin[3] = {false, false, false};
  double edge = 0.0;
  for (int round = 0; round < 3; ++round) {
    double product = 1.0;
    int axes = 0;
    for (int a = 0; a < 3; ++a) {
      if (!thin[a]) product *= extent[a], ++axes;
    }
    if (axes == 0) break;
    edge = std::pow(product / target, 1.0 / axes);
    bool changed = false;
    for (int a = 0; a < 3; ++a) {
      if (!thin[a] && extent[a] <= edge) thin[a] = changed = true;
    }
    if (!changed) break;
  }
  const double longest = std::max(extent[0], std::max(extent[1], extent[2]));
  edge = std::max(edge, longest / kMaxDim);
  return edge > 0.0 && std::isfinite(edge) ? edge : std::max(longest, 1.0);
}

} // namespace

BodyMotion motionOf(const Body& body, float dt) { return {poseAfter(body, dt), bodyTravel(body, dt)}; }

Status checkMotion(const Body& body, std::size_t index, float dt, Diagnostic* out_diag) {
  return checkMotion(body, motionOf(body, dt), index, out_diag);
}

Status checkMotion(const Body& body, const BodyMotion& motion, std::size_t index, Diagnostic* out_diag) {
  bool finite = std::isfinite(motion.travel) && isFinite(motion.end.t);
  for (float r : motion.end.r)
    finite = finite && std::isfinite(r);
  if (finite) return Status::kOk;
  const Vec3f v = body.linearVelocity(), w = body.angularVelocity();
  return writeDiagnostic(out_diag, Status::kInvalidArgument,
                         "body %zu: its velocities (linear %g %g %g, angular %g %g %g) give no finite motion over dt",
                         index, double(v.x), double(v.y), double(v.z), double(w.x), double(w.y), double(w.z));
}

// ---- The grid ----

namespace {

// The cells a box touches, per axis.
struct CellRange {
  std::uint32_t lo[3], hi[3];
  std::uint64_t cells() const { return std::uint64_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1); }
};

CellRange cellRange(const BodyIndex::Impl& grid, const Box& box) {
  const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
  CellRange r;
  for (int a = 0; a < 3; ++a)
    r.lo[a] = grid.cellOf(lo[a], a), r.hi[a] = grid.cellOf(hi[a], a);
  return r;
}

// Cells of `edge` from the scene box's low corner, as many as cover it (at most kMaxDim per axis).
void setCells(BodyIndex::Impl* grid, const double extent[3], double edge) {
  grid->inv_cell = float(1.0 / edge);
  for (int a = 0; a < 3; ++a) {
    grid->dims[a] = std::uint32_t(std::min(std::max(std::ceil(extent[a] / edge), 1.0), double(kMaxDim)));
    grid->last_cell[a] = float(grid->dims[a] - 1);
  }
}

} // namespace

void BodyIndex::Impl::boxInCells(const Box& box, std::uint32_t first, std::uint32_t last, int axis,
                                 std::uint32_t* out) const {
  const float lo = axis == 0 ? box.lo.x : axis == 1 ? box.lo.y : box.lo.z;
  const float hi = axis == 0 ? box.hi.x : axis == 1 ? box.hi.y : box.hi.z;
  for (std::uint32_t c = first; c <= last; ++c)
    out[c - first] = cell_box::field(axis, cell_box::quantize(lo, origin[axis], inv_cell, float(c))) |
                     cell_box::field(3 + axis, cell_box::quantize(hi, origin[axis], inv_cell, float(c)));
}

void BodyIndex::Impl::build(const Body* bodies, std::size_t body_count, float step_dt) {
  built = false;
  count = body_count;
  dt = step_dt;
  prepared.resize(count);
  boxes.resize(count);
  states.resize(count * kStateFloats);
  everywhere.clear();
  // Each body's boxes, the grown one exactly as the step grows it: the corners minus and plus the travel.
  std::vector<std::uint32_t> boxed; // bodies with a finite grown box
  boxed.reserve(count);
  const float inf = std::numeric_limits<float>::infinity();
  scene_lo = {inf, inf, inf};
  scene_hi = {-inf, -inf, -inf};
  for (std::size_t b = 0; b < count; ++b) {
    if (!unchanged[b]) { // else the last build's numbers for it stand
      prepared[b] = prepareStep(bodies[b], motions[b]);
      std::uint32_t* state = &states[b * kStateFloats];
      forEachState(bodies[b], [&](std::size_t k, std::uint32_t bits) { state[k] = bits; });
      const float t = motions[b].travel;
      const Vec3f lo = bodies[b].boundsMin(), hi = bodies[b].boundsMax();
      boxes[b].box[int(BodyBox::kBounds)] = {lo, hi};
      boxes[b].box[int(BodyBox::kGrown)] = {{lo.x - t, lo.y - t, lo.z - t}, {hi.x + t, hi.y + t, hi.z + t}};
    }
    const Box& grown = boxes[b].box[int(BodyBox::kGrown)];
    if (!isFinite(grown.lo) || !isFinite(grown.hi)) {
      everywhere.push_back(std::uint32_t(b));
      continue;
    }
    boxed.push_back(std::uint32_t(b));
    scene_lo = {minOf(scene_lo.x, grown.lo.x), minOf(scene_lo.y, grown.lo.y), minOf(scene_lo.z, grown.lo.z)};
    scene_hi = {maxOf(scene_hi.x, grown.hi.x), maxOf(scene_hi.y, grown.hi.y), maxOf(scene_hi.z, grown.hi.z)};
  }
  const bool any = !boxed.empty();
  const double extent[3] = {any ? double(scene_hi.x) - scene_lo.x : 0.0, any ? double(scene_hi.y) - scene_lo.y : 0.0,
                            any ? double(scene_hi.z) - scene_lo.z : 0.0};
  origin[0] = any ? scene_lo.x : 0.0f, origin[1] = any ? scene_lo.y : 0.0f, origin[2] = any ? scene_lo.z : 0.0f;
  auto grownBox = [&](std::uint32_t b) -> const Box& { return boxes[b].box[int(BodyBox::kGrown)]; };
  // Coarsen until the entries fit the budget; one cell always does.
  double edge = cellEdge(extent, std::max<std::size_t>(boxed.size(), 1));
  for (;;) {
    setCells(this, extent, edge);
    const std::uint64_t cells = std::uint64_t(dims[0]) * dims[1] * dims[2];
    std::uint64_t entries = 0;
    for (std::uint32_t b : boxed)
      entries += cellRange(*this, grownBox(b)).cells();
    if (cells == 1 || double(entries) <= kEntriesPerCellOrBody * double(cells + boxed.size())) break;
    edge *= 1.5;
  }
  // Counting sort into the cells, bodies in increasing index: every cell's list comes out sorted.
  const std::size_t cells = std::size_t(dims[0]) * dims[1] * dims[2];
  cell_start.assign(cells + 1, 0);
  auto forEachCell = [&](const CellRange& r, auto&& f) {
    for (std::uint32_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (std::uint32_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (std::uint32_t x = r.lo[0]; x <= r.hi[0]; ++x)
          f(cellIndex(x, y, z), x, y, z);
  };
  std::vector<CellRange> ranges(boxed.size()); // per boxed body, in the grid chosen
  for (std::size_t k = 0; k < boxed.size(); ++k) {
    ranges[k] = cellRange(*this, grownBox(boxed[k]));
    forEachCell(ranges[k], [&](std::size_t c, std::uint32_t, std::uint32_t, std::uint32_t) { ++cell_start[c + 1]; });
  }
  for (std::size_t c = 0; c < cells; ++c)
    cell_start[c + 1] += cell_start[c];
  cell_bodies.resize(cell_start[cells]);
  cell_boxes.resize(cell_start[cells] + 1); // one past the last entry: the kernels read entries in pairs
  std::vector<std::uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
  std::vector<std::uint32_t> along[3]; // a body's cell_box fields per cell along each axis
  for (int a = 0; a < 3; ++a)
    along[a].resize(dims[a]);
  for (std::size_t k = 0; k < boxed.size(); ++k) {
    const std::uint32_t b = boxed[k];
    const CellRange& r = ranges[k];
    for (int a = 0; a < 3; ++a)
      boxInCells(grownBox(b), r.lo[a], r.hi[a], a, along[a].data());
    forEachCell(r, [&](std::size_t c, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
      cell_boxes[fill[c]] = along[0][x - r.lo[0]] | along[1][y - r.lo[1]] | along[2][z - r.lo[2]];
      cell_bodies[fill[c]++] = b;
    });
  }
  findKinds(bodies);
  built = true;
}

bool BodyIndex::Impl::stateUnchanged(std::size_t b, const Body& body) const {
  const std::uint32_t* built_state = &states[b * kStateFloats];
  std::uint32_t differ = 0;
  forEachState(body, [&](std::size_t k, std::uint32_t bits) { differ |= bits ^ built_state[k]; });
  return differ == 0 && fieldUnchanged(prepared[b], body);
}

bool BodyIndex::Impl::bodyUnchanged(std::size_t b, const Body& body) const {
  if (!body.valid() || !stateUnchanged(b, body)) return false;
  // The box too: a body keeps the box it was placed with, and its field's grid may differ from the
  // one the build saw (a View opened again in place) while every number of its state is the same.
  const Box& box = boxes[b].box[int(BodyBox::kBounds)];
  const Vec3f lo = body.boundsMin(), hi = body.boundsMax();
  return std::memcmp(&box.lo, &lo, sizeof lo) == 0 && std::memcmp(&box.hi, &hi, sizeof hi) == 0;
}

void BodyIndex::Impl::refreshKinds(const Body* bodies) {
  for (std::size_t b = 0; b < count; ++b) {
    if (!sameMaterial(materials[b], bodies[b].material())) {
      findKinds(bodies);
      return;
    }
  }
}

void BodyIndex::Impl::findKinds(const Body* bodies) {
  constexpr int kRecentKinds = 8; // a city's buildings share one kind or a few
  std::int32_t recent[kRecentKinds];
  int known = 0;
  kinds.resize(count);
  materials.resize(count);
  for (std::size_t b = 0; b < count; ++b) {
    const Body& body = bodies[b];
    materials[b] = body.material();
    int k = 0;
    while (k < known &&
           !(bodies[recent[k]].field() == body.field() && sameMaterial(bodies[recent[k]].material(), body.material())))
      ++k;
    const std::int32_t kind = k < known ? recent[k] : std::int32_t(b);
    kinds[b] = kind;
    // The kind found moves to the front; a new one enters there, the oldest leaving when full.
    if (k == known && known < kRecentKinds) ++known;
    for (k = std::min(k, kRecentKinds - 1); k > 0; --k)
      recent[k] = recent[k - 1];
    recent[0] = kind;
  }
}

bool BodyIndex::Impl::kindsHold(const Body* bodies) const {
  for (std::size_t b = 0; b < count; ++b) {
    const std::int32_t kind = kinds[b];
    if (std::size_t(kind) != b && !sameMaterial(bodies[b].material(), bodies[kind].material())) return false;
  }
  return true;
}

bool BodyIndex::Impl::matches(const Body* bodies, std::size_t body_count, std::size_t* out_changed) const {
  if (body_count != count) {
    *out_changed = body_count;
    return false;
  }
  for (std::size_t b = 0; b < count; ++b) {
    if (!stateUnchanged(b, bodies[b])) {
      *out_changed = b;
      return false;
    }
  }
  return true;
}

// ---- BodyIndex ----

BodyIndex::BodyIndex() = default;
BodyIndex::~BodyIndex() = default;
BodyIndex::BodyIndex(BodyIndex&&) noexcept = default;
BodyIndex& BodyIndex::operator=(BodyIndex&&) noexcept = default;

Status BodyIndex::rebuild(const Body* bodies, std::size_t count, float dt, Diagnostic* out_diag) {
  const bool was_built = built();
  if (impl_ != nullptr) impl_->built = false; // until this rebuild succeeds
  if (!(dt > 0.0f) || !std::isfinite(dt))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "dt must be finite and > 0, got %g", double(dt));
  if (count > 0 && bodies == nullptr)
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "bodies is null but count is %zu", count);
  if (count >= (std::size_t(1) << 31))
    return writeDiagnostic(out_diag, Status::kInvalidArgument, "%zu bodies is too many for an index", count);
  try {
    if (impl_ == nullptr) impl_.reset(new Impl);
    // With the same count and dt, the last build's numbers for a body that has not changed stand (its
    // motion, its numbers for the step, its boxes): a scene where a few bodies move redoes those alone.
    // The comparison reads every number the checks below read, so an unchanged body would pass them again.
    const bool reuse = was_built && impl_->count == count && impl_->dt == dt;
    Impl& index = *impl_;
    index.motions.resize(count);
    index.unchanged.assign(count, 0);
    std::size_t kept = 0;
    // Each other body's motion, checked here and kept for the build.
    for (std::size_t b = 0; b < count; ++b) {
      if (reuse && index.bodyUnchanged(b, bodies[b])) {
        index.unchanged[b] = 1;
        ++kept;
        continue;
      }
      if (!bodies[b].valid()) return writeDiagnostic(out_diag, Status::kInvalidArgument, "body %zu is not valid", b);
      index.motions[b] = motionOf(bodies[b], dt);
      const Status motion = checkMotion(bodies[b], index.motions[b], b, out_diag);
      if (motion != Status::kOk) return motion;
    }
    // Every body as the last build saw it (a city's buildings at rest, frame after frame): that build's
    // grid stands too, and what this rebuild cost is the comparison.
    if (reuse && kept == count) {
      index.refreshKinds(bodies);
      index.built = true;
      return Status::kOk;
    }
    index.build(bodies, count, dt);
  } catch (const std::bad_alloc&) {
    impl_.reset(); // nothing of a build that ran out of memory is kept
    return writeDiagnostic(out_diag, Status::kOutOfMemory, "out of memory building an index of %zu bodies", count);
  }
  return Status::kOk;
}

bool BodyIndex::built() const { return impl_ != nullptr && impl_->built; }
std::size_t BodyIndex::bodyCount() const { return built() ? impl_->count : 0; }
float BodyIndex::dt() const { return built() ? impl_->dt : 0.0f; }

void BodyIndex::cellDims(std::uint32_t out_dims[3]) const {
  for (int a = 0; a < 3; ++a)
    out_dims[a] = built() ? impl_->dims[a] : 0;
}

std::size_t BodyIndex::bodiesNear(Vec3f lo, Vec3f hi, std::uint32_t* out, std::size_t capacity) const {
  if (!built()) return 0;
  std::size_t found = 0;
  NearBodies(impl_->count, impl_.get()).forEach(lo, hi, BodyBox::kGrown, [&](std::size_t b) {
    if (found < capacity) out[found] = std::uint32_t(b);
    ++found;
  });
  return found;
}

} // namespace dng
