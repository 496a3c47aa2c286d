// Counts points inside a closed mesh by the reference on its triangles (never a field): the judge of
// the demo's "particles inside" figure.
//   dng_count_inside MESH POSITIONS [MIN_DEPTH]
// POSITIONS holds "x y z" per line in the mesh's frame. Prints {"points":N,"inside":K,"deepest":D}
// where K counts points inside deeper than MIN_DEPTH (mesh units, default 0) and D is the deepest.
// Exit 0 when counted, 1 on bad arguments, 2 when a file cannot be read or POSITIONS holds anything
// but finite "x y z" triples (a point that is not a number could be counted as neither inside nor out).
#include "mesh_reference.h"
#include "stages.h"
#include "standard_output.h"

#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: dng_count_inside MESH POSITIONS [MIN_DEPTH]\n");
    return 1;
  }
  const float min_depth = argc > 3 ? std::stof(argv[3]) : 0.0f;
  dng::baker::TriangleSoup soup;
  const dng::baker::BakeStatus loaded = dng::baker::loadMesh(argv[1], &soup);
  dng::reference::MeshReference mesh;
  if (!loaded.ok() || !mesh.build(soup.vertices, soup.triangles)) {
    std::fprintf(stderr, "dng_count_inside: %s: %s\n", argv[1], loaded.ok() ? "no triangles" : loaded.message.c_str());
    return 2;
  }
  std::ifstream in(argv[2]);
  if (!in) {
    std::fprintf(stderr, "dng_count_inside: cannot read %s\n", argv[2]);
    return 2;
  }
  std::size_t points = 0, inside = 0;
  float deepest = 0.0f;
  dng::Vec3f p;
  while (in >> p.x >> p.y >> p.z) {
    if (!dng::isFinite(p)) {
      std::fprintf(stderr, "dng_count_inside: %s: point %zu is not finite\n", argv[2], points + 1);
      return 2;
    }
    ++points;
    if (!mesh.inside(p)) continue;
    const float depth = mesh.closest(p).distance;
    deepest = std::max(deepest, depth);
    inside += depth > min_depth ? 1 : 0;
  }
  if (!in.eof()) { // stopped on something that is not a number: "nan", "inf", a word, a cut line
    std::fprintf(stderr, "dng_count_inside: %s: unreadable after point %zu\n", argv[2], points);
    return 2;
  }
  std::printf("{\"points\":%zu,\"inside\":%zu,\"deepest\":%.6g}\n", points, inside, double(deepest));
  return dng::tools::finishStandardOutput("dng_count_inside", 0); // a lost count must not read as none
}
