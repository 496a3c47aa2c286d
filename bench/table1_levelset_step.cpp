// Stepping particles against a NanoVDB level set (table1_levelset.h): NanoVDB's headers only.
#include "dng/responses.h"
#include "table1_levelset.h"

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/SampleFromVoxels.h>

#include <cmath>

namespace dng {
namespace table1 {

namespace {

using Accessor = nanovdb::DefaultReadAccessor<float>;

// Distance and unnormalized gradient at the nearest voxel centre, by central differences.
inline void readNearest(const Accessor& acc, const nanovdb::Vec3f& index, float* distance, Vec3f* gradient) {
  const nanovdb::Coord ijk(int(std::floor(index[0] + 0.5f)), int(std::floor(index[1] + 0.5f)),
                           int(std::floor(index[2] + 0.5f)));
  *distance = acc.getValue(ijk);
  *gradient = {acc.getValue(ijk.offsetBy(1, 0, 0)) - acc.getValue(ijk.offsetBy(-1, 0, 0)),
               acc.getValue(ijk.offsetBy(0, 1, 0)) - acc.getValue(ijk.offsetBy(0, -1, 0)),
               acc.getValue(ijk.offsetBy(0, 0, 1)) - acc.getValue(ijk.offsetBy(0, 0, -1))};
}

template <class Read>
void stepWith(const nanovdb::FloatGrid& grid, Read read, float restitution, float collision_distance, float dt,
              Swarm* s) {
  for (std::size_t n = 0; n < s->size(); ++n) {
    const nanovdb::Vec3f index = grid.worldToIndexF(nanovdb::Vec3f(s->px[n], s->py[n], s->pz[n]));
    Contact contact;
    Vec3f gradient;
    read(index, &contact.distance, &gradient);
    Vec3f v = s->velocity(n);
    const float norm = length(gradient);
    if (norm > 0.0f) {
      contact.normal = gradient * (1.0f / norm);
      applyImpact(contact, restitution, collision_distance, dt, &v);
      s->vx[n] = v.x, s->vy[n] = v.y, s->vz[n] = v.z;
    }
    s->px[n] += v.x * dt, s->py[n] += v.y * dt, s->pz[n] += v.z * dt;
  }
}

} // namespace

void stepLevelSet(const nanovdb::GridHandle<nanovdb::HostBuffer>& levelset, LevelSetRead read, float restitution,
                  float collision_distance, float dt, Swarm* swarm) {
  const nanovdb::FloatGrid* grid = levelset.grid<float>();
  if (grid == nullptr) return;
  const Accessor acc = grid->getAccessor();
  if (read == LevelSetRead::kNearest) {
    stepWith(
        *grid, [&](const nanovdb::Vec3f& index, float* d, Vec3f* g) { readNearest(acc, index, d, g); }, restitution,
        collision_distance, dt, swarm);
    return;
  }
  // The sampler caches the eight values of the last cell it read, so value and gradient share them.
  auto sampler = nanovdb::createSampler<1>(acc);
  stepWith(
      *grid,
      [&](const nanovdb::Vec3f& index, float* d, Vec3f* g) {
        *d = sampler(index);
        const nanovdb::Vec3f grad = sampler.gradient(index);
        *g = {grad[0], grad[1], grad[2]};
      },
      restitution, collision_distance, dt, swarm);
}

} // namespace table1
} // namespace dng
