// Internal: the uniform grid behind dng::BodyIndex, and the loop over bodies that stepParticles runs
// with it or without it.
//
// Exactness: the step visits bodies in increasing index order and applies its own tests (the particle
// in the body's box, the move's box against the body's box grown by its travel) to each, so the index
// may skip only bodies those tests reject. The grid lists a superset of the rest: a body is entered
// in every cell its grown box touches, a query takes every cell its box touches, and both go through
// one monotone function from coordinate to cell, so boxes that overlap always share a cell. Then the
// index drops listed bodies by the same comparisons on the same floats as the step's tests (copies of
// the boxes, packed so that a query reads 24 bytes per listed body instead of the whole Body). The
// SIMD kernels list a lane's one cell by a coarse copy of each grown box (cell_box below), a superset
// that their own exact tests then narrow.
#pragma once

#include "dng/body.h"
#include "dng/body_index.h"
#include "pose.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace dng {

/// What a step needs of each body beyond the body itself: its pose at the end of the step and how far
/// any point of its box moves meanwhile. Out of line, in one place, so the step and the index compute
/// the same bits whatever the compiler inlines where.
struct BodyMotion {
  Pose end;
  float travel = 0.0f;
};
BodyMotion motionOf(const Body& body, float dt);
/// kInvalidArgument, naming body `index`, when its velocities do not give a finite motion over dt (a
/// velocity not finite, or one so large its travel overflows): the walk could not judge its moves.
Status checkMotion(const Body& body, std::size_t index, float dt, Diagnostic* out_diag);
/// The same for the motion motionOf(body, dt) already gave.
Status checkMotion(const Body& body, const BodyMotion& motion, std::size_t index, Diagnostic* out_diag);

/// One body as the SIMD kernels see it in a step: what follows from its field, pose and motion, computed
/// with the expressions the scalar path uses, so both paths compare the same numbers. Nothing of the
/// material, which may change without a rebuild (dng/body_index.h): the kernels read that from the
/// body. The index keeps one per body, so a chunk of lanes meeting a body reads one compact record
/// instead of preparing it from the Body, its motion and its field.
struct StepBody {
  const View* field = nullptr;
  bool dense = false;    ///< the field's encoding
  bool still = false;    ///< no velocity (linear and angular +0) and the end pose the start's, bit for bit
  Pose start, end;       ///< the body's pose at the start and at the end of the step
  Vec3f lo, hi;          ///< Body::boundsMin, boundsMax
  Vec3f linear, angular; ///< Body::linearVelocity, angularVelocity
  float travel = 0.0f;   ///< how far any point of its box moves in dt
  float band_world = 0.0f;
  // The walk's constants, local units (walk.h).
  float margin = 0.0f, reach = 0.0f, roomy = 0.0f, proof_level = 0.0f;
};
/// Out of line (step.cpp, beside the walk's margin), for the index and the step alike.
StepBody prepareStep(const Body& body, const BodyMotion& motion);

/// Whether `body` still has the field `prepared` (prepareStep's) was made for, with the numbers it took
/// from it: a View opened again in place may hold another file, and the kernels trust these numbers
/// (the encoding picks the lookup).
bool fieldUnchanged(const StepBody& prepared, const Body& body);

/// The sorted body lists a query box reads, or `all` when it must test every body.
struct CandidateLists {
  /// One cell per axis and a neighbour (2 x 2 x 2) plus the bodies listed everywhere. A box over more
  /// cells is a long move: it tests every body, as without an index.
  static constexpr int kMaxLists = 9;
  const std::uint32_t* begin[kMaxLists];
  const std::uint32_t* end[kMaxLists];
  int count = 0;
  bool all = false;
};

/// A world box; `which` of a body's boxes a query tests against.
struct Box {
  Vec3f lo, hi;
};
enum class BodyBox { kBounds = 0, kGrown = 1 };
/// A body's two boxes in one cache line: a particle's response reads one, its move the other.
struct alignas(64) BodyBoxes {
  Box box[2]; // by BodyBox
};

/// Each entry of a cell's list also holds its body's grown box within the cell, coarsely, so that the
/// lanes test a move against it with one 32-bit word instead of six floats (near_lanes.h): per axis,
/// the box's low and high ends in sixteenths of the cell, clamped to the cell, as six 4-bit fields
/// under a guard bit each. A move's box is quantized by the same expression. Every step of it is
/// monotone (a subtraction, multiplications by positive numbers, clamps, truncation of a non-negative
/// number), so a move that meets a box has fields that meet the box's: the test lists a superset of
/// what the exact test lists, which the exactness note above allows.
namespace cell_box {
constexpr int kSteps = 16;
constexpr int kFieldBits = 5; // 4 bits of value under a guard bit
constexpr std::uint32_t field(int k, std::uint32_t value) { return value << (kFieldBits * k); }
/// The box's low ends are fields 0-2 (x, y, z), its high ends fields 3-5.
constexpr std::uint32_t kLowValues = field(0, 15) | field(1, 15) | field(2, 15);
constexpr std::uint32_t kHighValues = field(3, 15) | field(4, 15) | field(5, 15);
constexpr std::uint32_t kGuards =
    field(0, 16) | field(1, 16) | field(2, 16) | field(3, 16) | field(4, 16) | field(5, 16);

/// The coordinate v of the axis whose origin, inverse cell edge and cell are given, in sixteenths of
/// that cell from its low wall, clamped to [0, 15]. The lanes repeat these operations in this order.
inline std::uint32_t quantize(float v, float origin, float inv_cell, float cell) {
  float f = ((v - origin) * inv_cell - cell) * float(kSteps);
  f = f > 0.0f ? f : 0.0f;
  f = f < float(kSteps - 1) ? f : float(kSteps - 1);
  return std::uint32_t(f);
}
} // namespace cell_box

/// Whether two materials act the same, bit for bit: their bytes from `response` through `swept`, which
/// hold no padding, so floats compare as bits (-0 and +0 differ) and the enum and bool as values.
inline bool sameMaterial(const Material& a, const Material& b) {
  static_assert(offsetof(Material, response) == 0 && sizeof(Response) == 4 && offsetof(Material, restitution) == 4 &&
                    offsetof(Material, swept) == 4 + 9 * sizeof(float),
                "sameMaterial compares Material's bytes up to `swept`: it must see every field and no padding");
  return std::memcmp(&a, &b, offsetof(Material, swept) + sizeof(bool)) == 0;
}

struct BodyIndex::Impl {
  bool built = false;
  std::size_t count = 0;
  float dt = 0.0f;
  std::vector<BodyMotion> motions; // per body
  std::vector<StepBody> prepared;  // per body, from its motion
  // Per body: its world box (Body::boundsMin/Max), and that box grown by the motion's travel as the step
  // grows it.
  std::vector<BodyBoxes> boxes;
  // What the build read of each body, to tell a stale index (BodyState).
  std::vector<std::uint32_t> states;
  // The grid: cells of edge 1 / inv_cell from origin, x fastest; cell c lists
  // cell_bodies[cell_start[c], cell_start[c + 1]), in increasing body index.
  float origin[3] = {0, 0, 0};
  float inv_cell = 1.0f;
  float last_cell[3] = {0, 0, 0}; // dims - 1, as floats for the clamp
  std::uint32_t dims[3] = {0, 0, 0};
  // The union of the finite grown boxes; empty (lo > hi) when there is none.
  Vec3f scene_lo, scene_hi;
  std::vector<std::uint32_t> cell_start;
  std::vector<std::uint32_t> cell_bodies;
  // Per entry of cell_bodies: the grown box in its cell (cell_box); then one unused word, so that the
  // SIMD kernels may load any entry together with the next one (near_lanes.h listOneCellEach).
  std::vector<std::uint32_t> cell_boxes;
  std::vector<std::uint32_t> everywhere; // bodies whose grown box is not finite (a NaN or huge velocity)
  // Per body, its kind: the body the build found with the same field and material (sameMaterial), or
  // itself. The build looks among the last few kinds it met only, so bodies of one kind may get
  // different kinds, which only costs them a shared pass (slot_lanes.h); never the reverse. Materials
  // may change after the build: the kinds hold for a call while every body's material still equals its
  // kind's (kindsHold).
  std::vector<std::int32_t> kinds;
  std::vector<Material> materials; // per body, as findKinds saw them
  // Per body, during a rebuild: 1 when it is as the last build saw it (bodyUnchanged), whose numbers
  // for it then stand.
  std::vector<std::uint8_t> unchanged;

  /// Builds the index. For every body, `unchanged` says whether the last build's numbers for it stand;
  /// `motions` must hold motionOf(bodies[b], step_dt) for every other body.
  void build(const Body* bodies, std::size_t body_count, float step_dt);
  /// Whether body b has the state (transform, velocities) and field that the build read (and that the
  /// step's staleness check compares: matches()).
  bool stateUnchanged(std::size_t b, const Body& body) const;
  /// For an index that was built: whether `body`, as body b, would give it the same numbers again. It
  /// is valid, and has the state, field and box the build read.
  bool bodyUnchanged(std::size_t b, const Body& body) const;
  /// findKinds again when a body's material changed since the kinds were found.
  void refreshKinds(const Body* bodies);
  void findKinds(const Body* bodies);
  /// Whether `kinds` still holds for `bodies`, which match the build's (matches()).
  bool kindsHold(const Body* bodies) const;
  /// The cell_box fields of `box` along `axis` (low end in field axis, high end in field 3 + axis) in
  /// the cells first to last along that axis, into out[0, last - first]; a cell's word ORs its three
  /// axes' fields.
  void boxInCells(const Box& box, std::uint32_t first, std::uint32_t last, int axis, std::uint32_t* out) const;

  /// Coordinate -> cell along `axis`, clamped to the grid. Monotone in x (a subtraction and a
  /// multiplication by a positive number, each rounded once, then clamps), which is all exactness
  /// needs: the build and every query call this one function.
  std::uint32_t cellOf(float x, int axis) const {
    float t = (x - origin[axis]) * inv_cell;
    t = t > 0.0f ? t : 0.0f;
    t = t < last_cell[axis] ? t : last_cell[axis];
    return std::uint32_t(t);
  }
  std::size_t cellIndex(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return (std::size_t(z) * dims[1] + y) * dims[0] + x;
  }

  /// The lists for the world box [lo, hi] (lo <= hi per axis, or NaN somewhere).
  void listsFor(Vec3f lo, Vec3f hi, CandidateLists* out) const {
    out->count = 0;
    out->all = false;
    if (!(hi.x >= scene_lo.x && hi.y >= scene_lo.y && hi.z >= scene_lo.z && lo.x <= scene_hi.x && lo.y <= scene_hi.y &&
          lo.z <= scene_hi.z)) {
      // Outside every finite box, the cheap answer for far particles; or NaN: every body.
      if (lo.x != lo.x || lo.y != lo.y || lo.z != lo.z || hi.x != hi.x || hi.y != hi.y || hi.z != hi.z) {
        out->all = true;
        return;
      }
      addEverywhere(out);
      return;
    }
    addEverywhere(out);
    const std::uint32_t x0 = cellOf(lo.x, 0), y0 = cellOf(lo.y, 1), z0 = cellOf(lo.z, 2);
    const std::uint32_t x1 = cellOf(hi.x, 0), y1 = cellOf(hi.y, 1), z1 = cellOf(hi.z, 2);
    if (x0 == x1 && y0 == y1 && z0 == z1) { // the common case: one cell
      addCell(cellIndex(x0, y0, z0), out);
      return;
    }
    const std::uint64_t cells = std::uint64_t(x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1);
    if (cells > std::uint64_t(CandidateLists::kMaxLists - out->count)) {
      out->all = true;
      return;
    }
    for (std::uint32_t z = z0; z <= z1; ++z)
      for (std::uint32_t y = y0; y <= y1; ++y)
        for (std::uint32_t x = x0; x <= x1; ++x)
          addCell(cellIndex(x, y, z), out);
  }
  void addEverywhere(CandidateLists* out) const {
    if (everywhere.empty()) return;
    out->begin[out->count] = everywhere.data();
    out->end[out->count++] = everywhere.data() + everywhere.size();
  }
  void addCell(std::size_t c, CandidateLists* out) const {
    if (cell_start[c] == cell_start[c + 1]) return;
    out->begin[out->count] = cell_bodies.data() + cell_start[c];
    out->end[out->count++] = cell_bodies.data() + cell_start[c + 1];
  }

  /// Whether `bodies` are still what the build saw; else the first body that changed, or count when
  /// the count differs.
  bool matches(const Body* bodies, std::size_t body_count, std::size_t* out_changed) const;
};

/// The bodies a step visits: all of them in order, or the index's candidates in order.
class NearBodies {
public:
  NearBodies(std::size_t count, const BodyIndex::Impl* index) : count_(count), index_(index) {}

  /// Calls f(b), in increasing b, for each body b whose box `which` may overlap the world box
  /// [lo, hi]: every body without an index; with one, only those whose box passes the step's own test
  /// (kBounds: contains the point lo == hi, as insideBounds; kGrown: overlaps [lo, hi], as
  /// segmentNearBounds).
  template <class F> void forEach(Vec3f lo, Vec3f hi, BodyBox which, F&& f) const {
    if (index_ == nullptr) {
      for (std::size_t b = 0; b < count_; ++b)
        f(b);
      return;
    }
    const BodyBoxes* boxes = index_->boxes.data();
    auto visit = [&](std::size_t b) {
      // The negated rejection, as the step writes it: a NaN bound rejects nothing there either.
      const Box& box = boxes[b].box[int(which)];
      if (hi.x < box.lo.x || hi.y < box.lo.y || hi.z < box.lo.z || lo.x > box.hi.x || lo.y > box.hi.y ||
          lo.z > box.hi.z)
        return;
      f(b);
    };
    CandidateLists lists;
    index_->listsFor(lo, hi, &lists);
    if (lists.all) { // not finite, or a long move: every body's box
      for (std::size_t b = 0; b < count_; ++b)
        visit(b);
      return;
    }
    if (lists.count == 1) {
      for (const std::uint32_t* b = lists.begin[0]; b != lists.end[0]; ++b)
        visit(std::size_t(*b));
      return;
    }
    merge(&lists, visit);
  }

private:
  // Visits the union of sorted lists in order: each round takes the smallest head and advances every
  // list that starts with it (a body in several cells is visited once).
  template <class F> static void merge(CandidateLists* lists, F& f) {
    for (;;) {
      std::uint32_t next = UINT32_MAX;
      for (int l = 0; l < lists->count; ++l) {
        if (lists->begin[l] != lists->end[l] && *lists->begin[l] < next) next = *lists->begin[l];
      }
      if (next == UINT32_MAX) return;
      f(std::size_t(next));
      for (int l = 0; l < lists->count; ++l) {
        if (lists->begin[l] != lists->end[l] && *lists->begin[l] == next) ++lists->begin[l];
      }
    }
  }

  std::size_t count_;
  const BodyIndex::Impl* index_;
};

} // namespace dng
