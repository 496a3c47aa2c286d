// What the stream samples (the paper's Figs. 6 and 7) report about a stream a disk emitted at an
// obstacle: the run's JSON line, then of the particles that started aimed at the obstacle (within half
// the disk's radius of its axis) the fraction that got past it and how far from the axis they went.
// Header-only.
#pragma once

#include "sample_particles.h"

#include <cstdio>
#include <vector>

namespace dng {
namespace samples {

/// The stream: emitted from a disk of `disk_radius` about `from`, flowing along `direction` (unit);
/// "past the obstacle" is farther than `past` along it.
struct StreamAxis {
  Vec3f from;
  Vec3f direction;
  float disk_radius;
  float past;
};

/// Prints the stream's two JSON lines. `start_offsets`: each particle's distance from the axis when
/// emitted; `distance(p, &normal)`: the obstacle's true signed distance (negative inside), by which the
/// particles inside are counted, never the field's. Returns the sample's exit code (exitCode): 1 when a
/// particle ended inside, 2 when its pictures or its lines were lost, else 0.
template <class Distance>
int reportStream(const char* name, const StreamAxis& axis, const Particles& particles,
                 const std::vector<float>& start_offsets, int steps, const StepTally& tally, bool pictures_written,
                 Distance distance) {
  const std::size_t count = particles.size();
  std::size_t aimed = 0, past = 0, inside = 0;
  double offset_sum = 0;
  for (std::size_t n = 0; n < count; ++n) {
    Vec3f normal;
    inside += distance(particles.position(n), &normal) < 0.0f ? 1 : 0;
    if (start_offsets[n] > 0.5f * axis.disk_radius) continue;
    ++aimed;
    const Vec3f p = particles.position(n) - axis.from;
    const float along = dot(p, axis.direction);
    if (along > axis.past) {
      ++past;
      offset_sum += length(p - axis.direction * along);
    }
  }
  std::printf("{\"sample\":\"%s\",\"particles\":%zu,\"steps\":%d,\"step_seconds\":%.4f,"
              "\"particle_steps_per_second\":%.4g,\"contacts\":%llu,\"inside\":%zu}\n",
              name, count, steps, tally.seconds, tally.particleStepsPerSecond(), (unsigned long long)tally.contacts,
              inside);
  const float fraction_downstream = aimed ? float(past) / float(aimed) : 0.0f;
  const float mean_offset = past ? float(offset_sum / double(past)) : 0.0f;
  std::printf("{\"sample\":\"%s\",\"fraction_downstream\":%.3f,\"mean_downstream_offset\":%.3f}\n", name,
              double(fraction_downstream), double(mean_offset));
  return exitCode(inside == 0 ? 0 : 1, pictures_written);
}

} // namespace samples
} // namespace dng
