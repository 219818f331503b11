// Loads a scene file through rigidae's public headers, shortens it, solves it
// into a folder and prints what the install test checks.
// Usage: consumer SCENE.toml OUT_DIR T_END
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <rigidae/app/solve.hpp>
#include <rigidae/io/scene_loader.hpp>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer SCENE.toml OUT_DIR T_END\n");
    return 2;
  }
  try {
    rigidae::Scene scene = rigidae::io::load_scene(argv[1]);
    scene.time.end = std::atof(argv[3]);
    const rigidae::SolveOutcome o = rigidae::solve_scene(scene, argv[2]);
    std::printf("status %s\n", rigidae::to_string(o.run.status).c_str());
    std::printf("t_reached %.17g\n", o.run.t_reached);
    std::printf("steps %ld\n", static_cast<long>(o.run.counters.steps));
    std::printf("energy %.17g\n", o.extremes.last.energy);
    std::printf("energy_rel_error %.3g\n", o.extremes.last.energy_error);
    return o.run.status == rigidae::RunStatus::Success ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
}
