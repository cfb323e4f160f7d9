#include "core/scene/discretization_twins.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>
#include <cstdlib>
#include <filesystem>

#include "core/scene/mesh_generator_keys.h"
#include "core/scene/schema_text.h"
#include "core/scene/scene.h"

namespace ff::scene {
namespace {

constexpr long long kFewestAcrossForAThirdLevel = 4;

// part i's part.mesh_size when Gmsh meshes it from geometry (mesh_generator_keys: part.mesh_size),
// else 0 (a generator, or a fixed mesh file)
double gmsh_mesh_size(const Document& d, std::size_t i) {
  return d.string("part.generator", i) == "file" ? d.number("part.mesh_size", i) : 0.0;
}

std::string part_key(std::size_t i, const std::string& key) { return "part[" + std::to_string(i) + "]." + key; }

// A mesh twin's overrides, `halvings` times coarser: generator parts at their element counts halved
// (rounded up) that many times, Gmsh parts at their sizes doubled as often (error_bars.md §5).
// Empty, with why in `why_not`, when a part cannot be coarsened: a twin coarser in some parts only
// would measure a mixture of errors.
// The counts of 2 or fewer are kept: a twin with one element across a strip puts a mid-width probe
// between two nodes and is no mesh of the strip; the directions kept are named in `kept`, and the
// twin's refinement ratio is then that of the directions halved (`ratio`: their geometric mean of
// n / n_twin; 0 when a Gmsh part makes the element counts the only measure, (R5)).
std::vector<std::string> coarser_mesh(const Document& d, int halvings, std::string* description, std::string* why_not,
                                      double* ratio, std::vector<std::string>* kept) {
  std::vector<std::string> out;
  std::string what;
  const double factor = std::ldexp(1.0, halvings);
  double log_ratio = 0.0;
  int halved = 0;
  bool gmsh = false;
  for (std::size_t i = 0; i < d.count("part"); ++i) {
    const std::string& generator = d.string("part.generator", i);
    if (generator == "file") {
      const double size = gmsh_mesh_size(d, i);
      if (size > 0) {  // meshed by Gmsh from geometry
        gmsh = true;
        out.push_back(part_key(i, "mesh_size") + "=" + text::number(factor * size));
        what += (what.empty() ? "" : ", ") + part_key(i, "mesh_size") + " = " + text::number(factor * size) + " (" +
                text::number(size) + ")";
        std::vector<double> local = d.numbers("part.local_sizes", i);
        if (!local.empty()) {
          std::string list;
          for (double s : local) list += (list.empty() ? "" : ", ") + text::number(factor * s);
          out.push_back(part_key(i, "local_sizes") + "=[" + list + "]");
          what += ", its local sizes x " + text::number(factor);
        }
        continue;
      }
      const std::string file = d.string("part.file", i);
      const bool script = std::filesystem::path(file).extension() == ".geo";
      *why_not = part_key(i, "file") + " ('" + file + "') " +
                 (script ? "is meshed at its script's own sizes; give part.mesh_size, which a twin can double"
                         : "is a fixed mesh, which no twin can coarsen faithfully");
      return {};
    }
    int part_halved = 0;
    for (const std::string& key : generator_count_keys(generator)) {
      if (key == "n3" && !d.present("part.n3", i)) continue;  // n3 absent follows n1
      const long long n = d.integer("part." + key, i);
      if (n <= 2) {  // kept: see above
        kept->push_back(part_key(i, key) + " = " + std::to_string(n));
        continue;
      }
      long long coarse = n;
      for (int h = 0; h < halvings; ++h) coarse = std::max(2LL, (coarse + 1) / 2);
      // each level must be coarser than the one before it
      long long previous = n;
      for (int h = 0; h + 1 < halvings; ++h) previous = (previous + 1) / 2;
      if (coarse >= previous) {
        *why_not = part_key(i, key) + " = " + std::to_string(n) + " cannot be halved " + std::to_string(halvings) +
                   " time(s) (" + std::to_string(1LL << halvings) + " elements there at least)";
        return {};
      }
      // a third level of fewer than 4 elements across (a quarter hemisphere of 2 x 2) is no mesh of
      // the run's problem: its observed order measures the coarse mesh's own behaviour (0.2-0.56 on
      // the hemisphere at 8 x 8, whose 4 x 4 twin alone gives the true error to 4 %), error_bars.md §5
      if (halvings >= 2 && coarse < kFewestAcrossForAThirdLevel) {
        *why_not = part_key(i, key) + " = " + std::to_string(n) + " halved twice leaves " + std::to_string(coarse) +
                   " elements, fewer than " + std::to_string(kFewestAcrossForAThirdLevel) +
                   " across: too coarse to show the run's order";
        return {};
      }
      out.push_back(part_key(i, key) + "=" + std::to_string(coarse));
      what += (what.empty() ? "" : ", ") + part_key(i, key) + " = " + std::to_string(coarse) + " (" + std::to_string(n) + ")";
      log_ratio += std::log(static_cast<double>(n) / static_cast<double>(coarse));
      ++halved, ++part_halved;
    }
    if (part_halved == 0) {
      *why_not = "part[" + std::to_string(i) + "] has no element count above 2 to halve";
      return {};
    }
  }
  *description = what;
  *ratio = gmsh || halved == 0 ? 0.0 : std::exp(log_ratio / halved);
  return out;
}

}  // namespace

TwinPlans discretization_twins(const std::string& path, const std::vector<std::string>& overrides, int levels) {
  const Document d = validate_file(scene_schema(path), path, overrides);
  TwinPlans plans;
  plans.on = d.boolean("output.error_bar");
  const std::string& model = d.string("scene.model");
  const bool shell = model == "shell";
  plans.dynamic = !shell || d.string("scene.analysis") == "dynamic";  // the hub-beam steps in time
  if (levels == 0) {  // the scene's; auto: three where a part is meshed by Gmsh in statics and eigen, else two
    // Generated meshes and their twins at half the counts are one family (every other node of the
    // run's is a twin's node), in which the formal order holds once the mesh resolves the answer;
    // a third level there mostly measured its own coarseness (a 4 x 4 hinged roof flagged a limit
    // load that is 0.02 % off). Gmsh meshes at twice the size are not nested, and a free face's
    // meshes scatter: there the third level checks the order (error_bars.md §5). In time a third
    // twin at 4 dt would cost more than the run.
    bool gmsh_part = false;
    for (std::size_t i = 0; shell && i < d.count("part"); ++i)  // the hub-beam has no [[part]]
      gmsh_part = gmsh_part || gmsh_mesh_size(d, i) > 0;
    const std::string& key = d.string("output.error_bar_levels");
    levels = key == "two" ? 2 : key == "three" ? 3 : !plans.dynamic && gmsh_part ? 3 : 2;
  }
  if (levels != 2 && levels != 3) throw std::invalid_argument("discretization_twins: two or three levels");
  plans.levels = levels;
  const double dt = plans.dynamic ? d.number("solver.dt") : 0.0;
  auto step = [&](int halvings) {  // solver.dt made 2^halvings times longer
    const double longer = std::ldexp(dt, halvings);
    return std::pair{"solver.dt=" + text::number(longer), "solver.dt = " + text::number(longer) + " (" + text::number(dt) + ")"};
  };
  // a shell structure's integrator estimates its own time-step error (R9): two levels need no time
  // twin, where the integrator damps what it cannot resolve (rho_inf < 1). Without numerical damping
  // the unresolved vibrations a step load excites never decay, and (R9) adds up their local errors
  // step after step although they never amount to more than their own small amplitude: on the
  // bundled step-loaded strip it gave 40 % for a 0.05 % error (error_bars.md §5). The time twin
  // measures that case.
  plans.local_time = shell && plans.dynamic && levels == 2 && d.number("solver.rho_inf") < 1.0;
  if (plans.dynamic && !plans.local_time) {
    const auto [set2, text2] = step(1);
    plans.twins.push_back({"time", {set2}, text2});
    if (levels == 3) {
      const auto [set4, text4] = step(2);
      plans.twins.push_back({"time_coarser", {set4}, text4});
    }
  }
  if (!shell) {
    plans.missing.push_back("no mesh estimate: the hub-beam's twins are in time only (its EFG and FEM "
                            "discretizations are compared with each other in its verification)");
    return plans;
  }
  for (int halvings = 1; halvings < levels; ++halvings) {
    std::string description, why_not = "the scene has no shell part to coarsen";
    double ratio = 0.0;
    std::vector<std::string> kept;
    std::vector<std::string> mesh = coarser_mesh(d, halvings, &description, &why_not, &ratio, &kept);
    if (halvings == 1 && !kept.empty()) {
      std::string list;
      for (const std::string& k : kept) list += (list.empty() ? "" : ", ") + k;
      plans.missing.push_back("the mesh estimate leaves out " + list + ": kept in the twins (a twin needs 2 elements "
                              "across), so only the other directions' error is measured");
    }
    if (mesh.empty()) {  // a third level that cannot be made leaves the two-level estimate
      plans.missing.push_back(std::string(halvings == 1 ? "no mesh estimate: " : kNoThirdMeshLevel) +
                              why_not);
      if (halvings == 2 && plans.twins.size() == 1) plans.levels = 2;  // the mesh twin was the only one
      return plans;
    }
    const std::string name = halvings == 1 ? "mesh" : "mesh_coarser";
    if (plans.dynamic && !plans.local_time) {  // (R8): the mesh estimate from twins at 2 dt
      const auto [set2, text2] = step(1);
      mesh.push_back(set2);
      plans.twins.push_back({name + "_at_2dt", mesh, description + ", " + text2, ratio});
    } else {
      plans.twins.push_back({name, mesh, description, ratio});
    }
  }
  return plans;
}

}  // namespace ff::scene
