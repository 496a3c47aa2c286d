// The full leak table (issue #10): every mesh and normal mode against every case, 20,000 particles for
// 120 steps each, and the scenes of several bodies (scene_case.h), written as markdown (docs/LEAKS.md
// through `bash setup.sh leaks`).
//   leak_report MESH_DIR OUTPUT.md [PARTICLES] [STEPS]
//   leak_report --mesh FILE [--mesh FILE ...] [--resolution N] OUTPUT.md [PARTICLES] [STEPS]
// MESH_DIR holds bunny00.off, fandisk.off, blade.off and cheese.off. With --mesh, the same cases run on those mesh
// files instead (OBJ, OFF, PLY or STL), each judged closed or open as checkMesh finds it, in the
// normal-blur and exact modes, and in potential mode too when it is open; --resolution bakes them at N
// voxels along the longest axis instead of 64 (the code-made meshes of the standard table are sized for
// 64, so it goes with --mesh only). Exit code 0 when the table was
// written, 1 on bad arguments or a mesh that would not load or bake; leaks do not change it (the table
// is the verdict).
#include "leak_case.h"
#include "path_judge.h"
#include "scene_case.h"
#include "temp_dir.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace dng::leak;
using dng::baker::NormalMode;

// One mesh in one normal mode.
struct Entry {
  LeakMesh mesh;
  NormalMode mode;
};

// The table of docs/LEAKS.md: the real meshes from `mesh_dir`, then the code-made hard cases.
bool standardEntries(const std::string& mesh_dir, std::vector<Entry>* out, std::string* out_error) {
  struct Real {
    const char* file;
    const char* name;
    std::vector<NormalMode> modes;
  };
  const Real real[] = {
      {"bunny00.off", "bunny", {NormalMode::kNormalBlur, NormalMode::kExact}},
      {"fandisk.off", "fandisk", {NormalMode::kNormalBlur, NormalMode::kExact}},
      {"blade.off", "blade", {NormalMode::kPotential, NormalMode::kNormalBlur, NormalMode::kExact}}, // open
      {"cheese.off", "cheese", {NormalMode::kNormalBlur, NormalMode::kExact}},
  };
  for (const Real& r : real) {
    LeakMesh mesh;
    if (!loadMeshFile(mesh_dir + "/" + r.file, r.name, &mesh, out_error)) return false;
    for (NormalMode mode : r.modes)
      out->push_back({mesh, mode});
  }
  const std::pair<LeakMesh (*)(), std::vector<NormalMode>> made[] = {
      {thinPlate, {NormalMode::kNormalBlur, NormalMode::kExact, NormalMode::kPotential}},
      {concaveNotch, {NormalMode::kNormalBlur, NormalMode::kExact}},
      {rodsAndFins, {NormalMode::kNormalBlur, NormalMode::kExact}},
      {hollowBox, {NormalMode::kNormalBlur, NormalMode::kExact}},
      {closeFins, {NormalMode::kNormalBlur, NormalMode::kExact}},
  };
  for (const auto& [make, modes] : made) {
    for (NormalMode mode : modes)
      out->push_back({make(), mode});
  }
  return true;
}

// Mesh files the harness knows nothing about, named by their file names.
bool meshEntries(const std::vector<std::string>& paths, std::vector<Entry>* out, std::string* out_error) {
  for (const std::string& path : paths) {
    LeakMesh mesh;
    const std::string name = path.substr(path.find_last_of('/') + 1);
    if (!loadMeshFile(path, name, &mesh, out_error)) return false;
    if (!mesh.closed) out->push_back({mesh, NormalMode::kPotential});
    out->push_back({mesh, NormalMode::kNormalBlur});
    out->push_back({mesh, NormalMode::kExact});
  }
  return true;
}

std::vector<CaseSpec> cases() {
  std::vector<CaseSpec> out;
  const auto add = [&](const char* name, Motion motion, Responses responses, bool swept, float speed, Start start,
                       Stepper stepper) {
    out.push_back({name, motion, responses, swept, speed, start, stepper});
  };
  add("static, impact", Motion::kStatic, Responses::kImpact, false, 1, Start::kAround, Stepper::kDngrid);
  add("static, impact + drag + flow", Motion::kStatic, Responses::kImpactDragFlow, false, 1, Start::kAround,
      Stepper::kDngrid);
  add("static, spring", Motion::kStatic, Responses::kSpring, false, 1, Start::kAround, Stepper::kDngrid);
  add("translating, impact", Motion::kTranslating, Responses::kImpact, false, 1, Start::kAround, Stepper::kDngrid);
  add("spinning, impact", Motion::kSpinning, Responses::kImpact, false, 1, Start::kAround, Stepper::kDngrid);
  add("scaled x2.5, impact", Motion::kScaled, Responses::kImpact, false, 1, Start::kAround, Stepper::kDngrid);
  add("resting under gravity, impact", Motion::kStatic, Responses::kImpact, false, 1, Start::kResting,
      Stepper::kDngrid);
  add("swept at 10x, static", Motion::kStatic, Responses::kImpact, true, 10, Start::kAround, Stepper::kDngrid);
  add("swept at 10x, spinning", Motion::kSpinning, Responses::kImpact, true, 10, Start::kAround, Stepper::kDngrid);
  add("control: ray caster, static", Motion::kStatic, Responses::kImpact, false, 1, Start::kAround,
      Stepper::kRayCaster);
  add("control: ray caster, spinning", Motion::kSpinning, Responses::kImpact, false, 1, Start::kAround,
      Stepper::kRayCaster);
  return out;
}

std::string thousands(unsigned long long n) {
  std::string s = std::to_string(n);
  for (int i = int(s.size()) - 3; i > 0; i -= 3)
    s.insert(std::size_t(i), ",");
  return s;
}

std::string fixed(float value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, double(value));
  return text;
}

// One table row. Open meshes have no inside: their depth columns read "-".
std::string row(const std::string& name, bool closed, const CaseResult& r) {
  std::ostringstream o;
  o << "| " << name << " | " << thousands(r.crossing_steps) << " | " << thousands(r.entered) << " / "
    << thousands(r.left) << " / " << thousands(r.through) << " | **" << thousands(r.visible_leaks) << "** | "
    << thousands(r.thin_passes) << " | " << (closed ? fixed(r.deepest, 2) : "-") << " | "
    << (closed ? fixed(r.median_depth, 3) : "-") << " | "
    << (closed ? thousands(r.inside_at_end) : thousands(r.other_side_at_end)) << " | " << thousands(r.contacts) << " | "
    << thousands(r.fast_steps) << " |\n";
  return o.str();
}

// One subject's totals for the summary: what issue #10's goals count.
struct Totals {
  std::string label;
  bool scenes = false; ///< no control runs: that column reads "-"
  unsigned long long design_crossings = 0, design_visible = 0, design_at_end = 0, swept_crossings = 0,
                     control_crossings = 0;

  void add(const CaseSpec& spec, const CaseResult& r) {
    if (spec.stepper == Stepper::kRayCaster)
      control_crossings += r.crossing_steps;
    else if (spec.swept)
      swept_crossings += r.crossing_steps;
    else
      addDesign(r);
  }
  void addDesign(const CaseResult& r) {
    design_crossings += r.crossing_steps;
    design_visible += r.visible_leaks;
    design_at_end += r.inside_at_end + r.other_side_at_end;
  }
  std::string row() const {
    return "| " + label + " | " + thousands(design_crossings) + " | **" + thousands(design_visible) + "** | **" +
           thousands(design_at_end) + "** | **" + thousands(swept_crossings) + "** | " +
           (scenes ? "-" : thousands(control_crossings)) + " |\n";
  }
};

const char* kTitle = R"(# Leaks: particles against the original triangles

Written by `bash setup.sh leaks` (tests/leak/leak_report.cpp); do not edit by hand. The fast subset of
these cases runs in the test suite as `leak_test`. [LEAKS_MORE.md](LEAKS_MORE.md) runs the same cases on
more meshes.
)";

// The title of a table of meshes given with --mesh.
const char* kMeshesTitle = R"(# Leaks on more meshes

Written by `bash setup.sh leaks` (tests/leak/leak_report.cpp, `--mesh`); do not edit by hand. The cases
of [LEAKS.md](LEAKS.md) on meshes its table does not hold, named by their files. Each is judged closed
(no boundary or non-manifold edge: the baker's mesh report) or open, and baked in the normal-blur and
exact modes, and in potential mode too when it is open. A closed mesh that intersects itself is closed
by that test, but there the judge's ray parity and the field's sign can disagree about what is inside.
)";

const char* kMethod = R"(
## Method

Each mesh is baked at resolution RESOLUTION with the band `dngbake --max-speed --dt 0.016` gives for 3 voxels per
step, so the design speed is `View::guaranteedReach()` x body scale / dt (3.5 voxels per step).
Real meshes are moved so that their bounding-box centre is the origin; the code-made ones are built in
voxels (the plate is 0.5 voxel thick, the rods 0.6, the fins 0.4, the hollow box's walls 1, the close
fins 1.5 thick with 2-voxel gaps, the notch is a 90-degree concave edge).

Particles start outside the solid (ray parity on the triangles; either side of an open mesh) between
0.1 voxel and the guaranteed reach from the surface, half of them aimed at the nearest surface point,
with speeds relative to the surface up to the case's limit (the design speed; 10x for swept cases).
Gravity adds at most 0.1 design speed over the run. Moving bodies: before step k the body is placed at
its pose at t_k with its velocity (translating at half the design speed; spinning so that its farthest
vertex moves at half the design speed); with constant velocities its pose after the step is exactly its
pose at t_k + dt. Materials: impact with restitution 0.5 and collision distance 0.1 voxel; drag 2/s
within 1 voxel and surface flow 3 design speeds/s within 2 voxels; a spring stiff enough to stop a
design-speed particle within the band.

Every step is judged in the mesh's own frame, never by the field: the straight path from the particle's
start (through the body's pose before the step) to its end (through the pose after it) is tested against
the original triangles with Embree (every crossing of the segment; the closest point for depth, sampled
every 0.05 voxel along the parts of the path inside; ray parity for inside, by a majority of three rays
that meet no triangle edge).

- **crossings**: particle-steps whose path meets the surface at all, split by kind: **entered** (ends
  inside), **left** (starts inside), **through** (starts and ends outside: cut a corner or passed a thin
  part).
- **visible leaks**: steps that get in (entered or through) and go deeper than 0.1 voxel on the way, end
  deeper than 0.05 voxel, or pass a thin part (enter and leave through opposite-facing faces). On an open
  mesh every crossing passes the sheet, so every crossing is a visible leak.
- **thin passes**: of those, the passes through a thin part (open mesh: every crossing).
- **deepest**, **median**: the deepest point of crossing paths inside the solid, in voxels.
- **at end**: closed meshes, particles more than 0.05 voxel inside after the last step; open meshes,
  particles on the other side of the sheet from where they started (an odd number of crossings).
- **contacts**: particle-steps in which the body acted (the ray caster: a hit). **too fast**: steps
  begun inside the grid's box with a speed relative to the surface above the case's limit (rebounds from
  springs and flow may add speed; those steps test beyond the design).

The scaled case is the static one magnified 2.5 times, with the same particles and the same paths in
the mesh's frame: equal figures there show that the step does not depend on the body's scale. A path
that clips a sharp edge enters and leaves through faces facing apart, so it counts as a thin pass too:
the tip of a wedge is a thin part.

The **control** rows step the same particles with an exact ray caster (each step's path cast at the
triangles, stopped a thousandth of a voxel short of the first hit and reflected): it must show 0
crossings, or the harness is wrong.
)";

const char* kScenesTitle = R"(
## Several bodies

Scenes of several bodies moving at once (tests/leak/scene_case.cpp): the same particles judged every step
against each body's own triangles in that body's frame, the counts summed over the bodies. Boxes made in
code: a ground 120 x 26 x 4 units and a wall 2 x 26 x 12 (voxels of 1 unit), crates 8 units wide (voxels
of 0.4, guaranteed reach 1.4 units: they set those scenes' design speed); and bunny and fandisk, each on
a ground box of its own, measured in its own voxels. Speeds are fractions of the slowest body's design
speed; where a body must stop 1 unit short of another, its start follows from its speed, and each scene
runs the steps its motion is laid out for (30 to 60; the STEPS argument does not apply). Resting
particles start 0.15 unit above the crates' ground (half a voxel above the meshes'), under gravity;
thrown ones at random directions with speeds up to 0.3 design speed. A particle that a moving body pushes
bounces off it and may meet another body faster than the design speed: those steps count as *too fast*.
Every scene runs with each of the single-body cases' materials on every body: impact, impact + drag +
flow, and the spring (whose rebounds are most of its *too fast* steps); a scene of thrown particles runs
once more swept, with impact, the particles up to ten times the design speed relative to the bodies. The
summary counts those rows' crossings as swept ones.
)";

// Random scenes per normal mode (SceneSet::random, seed 1), their movers at up to this many design speeds:
// with particles thrown at up to 0.3 and gravity's 0.1, relative speeds stay within the design speed.
constexpr int kRandomScenes = 100;
constexpr float kRandomSpeed = 0.6f;

const char* kRandomTitle =
    R"( scenes per mode from one seed (SceneSet::random): two to four movers, 8-unit crates, rods 2
units thick and slabs 1.5 thick (voxels of 0.4 for the crates, 1 for the rest), over a ground 120 units
square, each sliding along it or spinning about a random axis 0.05 or 1 unit above it, at up to SPEED times
the design speed, their paths kept 1 unit apart; particles (half the table's count) resting on the ground
or thrown above it at up to 0.3 design speed; impact, impact + drag + flow or spring on every body.
Their counts summed; *scenes with a crossing*: how many of them had any. The second row of each mode runs
the scenes with thrown particles again, swept, the particles up to ten times the design speed relative
to the bodies.
)";

// The scenes of several bodies: a table and a summary row per normal mode, in the order the modes come.
class SceneTables {
public:
  /// Runs the boxes' scenes the first time `subject`'s mode comes, then the scenes around `subject`.
  bool add(const Subject& subject, const dng::testing::TempDir& folder, long particles) {
    const std::string mode = dng::baker::normalModeName(subject.mode);
    std::string error;
    if (std::find(modes_.begin(), modes_.end(), mode) == modes_.end()) {
      modes_.push_back(mode);
      totals_[mode] = {"scenes of several bodies, " + mode, true};
      const auto boxes = SceneSet::boxes(subject.mode, folder.path().string(), &error);
      if (!boxes) return fail(error);
      run(*boxes, mode, particles);
      const auto random =
          SceneSet::random(subject.mode, kRandomScenes, 1, kRandomSpeed, folder.path().string(), &error);
      if (!random) return fail(error);
      runRandom(*random, mode, particles / 2, false);
      runRandom(*random, mode, particles / 2, true);
    }
    const auto around = SceneSet::aroundMesh(subject, folder.path().string(), &error);
    if (!around) return fail(error);
    run(*around, mode, particles);
    return true;
  }

  void writeTotals(std::ostream& out) const {
    for (const std::string& mode : modes_)
      out << totals_.at(mode).row();
  }

  void writeTables(std::ostream& out) const {
    if (modes_.empty()) return;
    out << kScenesTitle;
    std::string title = kRandomTitle;
    title.replace(title.find("SPEED"), 5, fixed(kRandomSpeed, 1));
    out << "\n### Random scenes\n\n"
        << kRandomScenes << title
        << "\n| mode | scenes | particle-steps | crossings | visible leaks | deepest (voxel) | inside at end | scenes "
           "with a crossing | contacts | too fast |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string& mode : modes_)
      out << random_rows_.at(mode);
    for (const std::string& mode : modes_)
      out << "\n### " << mode
          << "\n\n| scene | crossings | entered / left / through | visible leaks | thin passes | deepest (voxel) | "
             "median (voxel) | inside at end | contacts | too fast "
             "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
          << rows_.at(mode);
  }

private:
  static bool fail(const std::string& error) {
    std::fprintf(stderr, "leak_report: %s\n", error.c_str());
    return false;
  }

  void run(const SceneSet& set, const std::string& mode, long particles) {
    const std::pair<Responses, const char*> materials[] = {{Responses::kImpact, "impact"},
                                                           {Responses::kImpactDragFlow, "impact + drag + flow"},
                                                           {Responses::kSpring, "spring"}};
    for (SceneSpec scene : set.scenes()) {
      scene.particles = std::size_t(particles);
      for (const auto& [responses, material] : materials) {
        scene.responses = responses;
        runRow(scene, scene.name + ", " + material, mode);
      }
      if (scene.spawn_speed > 0.0f) { // thrown particles: once more, swept and ten times as fast
        SceneSpec fast = swept(scene);
        runRow(fast, scene.name + ", swept, particles at 10x", mode);
      }
    }
  }

  void runRow(const SceneSpec& scene, const std::string& name, const std::string& mode) {
    const CaseResult r = runScene(scene);
    std::fprintf(stderr, "leak_report: scene, %s, %s: %llu crossings, %llu visible (%.1f s)\n", mode.c_str(),
                 name.c_str(), (unsigned long long)r.crossing_steps, (unsigned long long)r.visible_leaks, r.seconds);
    rows_[mode] += row(name, true, r);
    if (scene.swept)
      totals_[mode].swept_crossings += r.crossing_steps;
    else
      totals_[mode].addDesign(r);
  }

  // The scene with swept bodies and impact, its thrown particles up to ten times the design speed
  // relative to the bodies (the bodies' own speed taken off).
  static SceneSpec swept(SceneSpec scene) {
    scene.swept = true;
    scene.responses = Responses::kImpact;
    scene.spawn_speed *= 10.0f / 0.3f - 2.0f;
    return scene;
  }

  // The random scenes of one mode, summed into one row; swept: their thrown particles at 10x, swept.
  void runRandom(const SceneSet& set, const std::string& mode, long particles, bool fast) {
    CaseResult sum;
    int scenes = 0, crossed = 0;
    for (SceneSpec scene : set.scenes()) {
      scene.particles = std::size_t(particles);
      if (fast) {
        if (!(scene.spawn_speed > 0.0f)) continue;
        scene = swept(scene);
      }
      ++scenes;
      const CaseResult r = runScene(scene);
      if (fast)
        totals_[mode].swept_crossings += r.crossing_steps;
      else
        totals_[mode].addDesign(r);
      crossed += r.crossing_steps > 0 ? 1 : 0;
      addCounts(r, &sum);
    }
    const std::string label = mode + (fast ? ", thrown particles at 10x, swept" : "");
    std::fprintf(stderr, "leak_report: %d random scenes, %s: %llu crossings, %llu visible\n", scenes, label.c_str(),
                 (unsigned long long)sum.crossing_steps, (unsigned long long)sum.visible_leaks);
    random_rows_[mode] += "| " + label + " | " + std::to_string(scenes) + " | " + thousands(sum.particle_steps) +
                          " | " + thousands(sum.crossing_steps) + " | **" + thousands(sum.visible_leaks) + "** | " +
                          fixed(sum.deepest, 2) + " | **" + thousands(sum.inside_at_end) + "** | " +
                          std::to_string(crossed) + " | " + thousands(sum.contacts) + " | " +
                          thousands(sum.fast_steps) + " |\n";
  }

  std::vector<std::string> modes_;
  std::map<std::string, std::string> rows_, random_rows_;
  std::map<std::string, Totals> totals_;
};

// A whole number from 1 to 10^8, the whole of `text`.
bool positiveCount(const std::string& text, long* out) {
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < 1 || value > 100000000) return false;
  *out = value;
  return true;
}

int usage() {
  std::fprintf(stderr, "usage: leak_report MESH_DIR OUTPUT.md [PARTICLES] [STEPS]\n"
                       "       leak_report --mesh FILE [--mesh FILE ...] [--resolution N] OUTPUT.md [PARTICLES] "
                       "[STEPS]\n");
  return 1;
}

} // namespace

int main(int argc, char** argv) {
  std::vector<std::string> meshes, positional;
  std::string resolution_text;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg != "--mesh" && arg != "--resolution")
      positional.push_back(arg);
    else if (a + 1 >= argc)
      return usage();
    else if (arg == "--mesh")
      meshes.push_back(argv[++a]);
    else
      resolution_text = argv[++a];
  }
  long resolution = dng::leak::kResolution;
  if (!resolution_text.empty() &&
      (meshes.empty() || !positiveCount(resolution_text, &resolution) || resolution < 16 || resolution > 1024)) {
    std::fprintf(stderr, "leak_report: --resolution goes with --mesh and must be a whole number from 16 to 1024\n");
    return 1;
  }
  const std::size_t first = meshes.empty() ? 1 : 0; // the output's place among the positional arguments
  if (positional.size() < first + 1 || positional.size() > first + 3) return usage();
  const std::string output = positional[first];
  long particles = 20000, steps = 120;
  if ((positional.size() > first + 1 && !positiveCount(positional[first + 1], &particles)) ||
      (positional.size() > first + 2 && !positiveCount(positional[first + 2], &steps))) {
    std::fprintf(stderr, "leak_report: PARTICLES and STEPS must be whole numbers from 1 to 10^8\n");
    return 1;
  }
  std::vector<Entry> entries;
  std::string error;
  if (!(meshes.empty() ? standardEntries(positional[0], &entries, &error) : meshEntries(meshes, &entries, &error))) {
    std::fprintf(stderr, "leak_report: %s\n", error.c_str());
    return 1;
  }
  dng::testing::TempDir folder("leak_report");
  std::ostringstream md;
  std::vector<Totals> totals;
  SceneTables scenes;
  for (const Entry& entry : entries) {
    const LeakMesh& mesh = entry.mesh;
    const auto subject = bakeSubject(mesh, entry.mode, folder.path().string(), &error, int(resolution));
    if (!subject) {
      std::fprintf(stderr, "leak_report: %s\n", error.c_str());
      return 1;
    }
    totals.push_back({subject->label()});
    md << "\n## " << subject->label() << " (" << thousands(mesh.mesh.triangles.size()) << " triangles, "
       << (mesh.closed ? "closed" : "open") << ", voxel " << subject->voxel << ", reach "
       << fixed(subject->reach / subject->voxel, 2) << " voxels)\n\n";
    md << "| case | crossings | entered / left / through | visible leaks | thin passes | deepest (voxel) | median "
          "(voxel) | "
       << (mesh.closed ? "inside" : "other side") << " at end | contacts | too fast |\n";
    md << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (CaseSpec c : cases()) {
      c.particles = std::size_t(particles);
      c.steps = int(steps);
      const CaseResult r = runCase(*subject, c);
      std::fprintf(stderr, "leak_report: %s, %s: %llu crossings, %llu visible (%.1f s)\n", subject->label().c_str(),
                   c.name.c_str(), (unsigned long long)r.crossing_steps, (unsigned long long)r.visible_leaks,
                   r.seconds);
      md << row(c.name, mesh.closed, r);
      totals.back().add(c, r);
    }
    // The scenes of several bodies, in fandisk's modes, in the standard table only.
    if (meshes.empty() && (mesh.name == "bunny" || mesh.name == "fandisk") && !scenes.add(*subject, folder, particles))
      return 1;
  }
  std::ofstream out(output);
  std::string method = kMethod;
  const std::string placeholder = "RESOLUTION";
  method.replace(method.find(placeholder), placeholder.size(), std::to_string(resolution));
  out << (meshes.empty() ? kTitle : kMeshesTitle) << method << "\n"
      << thousands(static_cast<unsigned long long>(particles)) << " particles, " << steps
      << " steps of 0.016 s per case.\n";
  out << "\n## Summary\n\nThe goals of issue #10 are 0 in the bold columns. *Design speed*: the seven dngrid cases "
         "above the swept ones (static, drag + flow, spring, translating, spinning, scaled, resting), and for the "
         "scenes of several "
         "bodies every scene not swept (the swept ones count as swept); *at end*: "
         "particles inside deeper than 0.05 voxel, or on the other side of an open sheet.\n\n";
  out << "| mesh | crossings at design speed | visible leaks | at end | swept 10x crossings | control crossings |\n";
  out << "|---|---:|---:|---:|---:|---:|\n";
  for (const Totals& t : totals)
    out << t.row();
  scenes.writeTotals(out);
  out << md.str();
  scenes.writeTables(out);
  out.close(); // the last buffer is written here, and may fail here
  if (!out) {
    std::fprintf(stderr, "leak_report: cannot write %s\n", output.c_str());
    return 1;
  }
  return 0;
}
