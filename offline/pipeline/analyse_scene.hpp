#pragma once
// `flexloop analyse SCENE`: the passive machine, the PI force-feedback design and the closed
// loop of a scene (DESIGN.md §4), printed and written to a directory.
#include <string>

namespace flexloop::cli {

struct FrequencyGrid {
  double f_min_hz, f_max_hz;
  int points;
};

void analyse_scene(const std::string& scene_path, const std::string& out_dir,
                   const FrequencyGrid& grid);

}  // namespace flexloop::cli
