#pragma once
// MJCF (MuJoCo's XML model format) from a scene: `rigidae export --mjcf
// SCENE -o model.xml` (src/io/mjcf_writer.cpp has the rules). The scene is
// written as the system it runs as (as_system): a one-body scene is its body
// on a ball joint at the fixed point (a free body: at its centre of mass).
#include <string>
#include <utility>
#include <vector>

#include "rigidae/model/scene.hpp"

namespace rigidae::io {

struct MjcfOptions {
  double timestep = 1e-4;        // s, <option timestep>
  std::string integrator = "RK4";  // <option integrator>: RK4, Euler or implicit
  // Bodies nested in one file at most: MuJoCo's XML reader (tinyxml2) stops
  // at 100 nested elements, so deeper trees continue in <include>d files.
  int bodies_per_file = 40;
};

// The model as files: (name, text), the main one first, named `main_name`;
// the others `STEM.partK.xml` beside it, <include>d where the nesting is cut.
// Throws InputError for what MJCF cannot hold here: closed loops,
// particles, springs and loads.
std::vector<std::pair<std::string, std::string>> mjcf_files(const Scene& scene, const MjcfOptions& options,
                                                            const std::string& main_name);

}  // namespace rigidae::io
