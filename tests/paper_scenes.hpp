// The scenes of the tests that run every paper scene: every scenes/*.json (the paper scenes and
// their multi-light variants; scenes/stress/ is a sub-folder and not included), by name, sorted.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace tp::host {

inline std::vector<std::string> paper_scenes() {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(TP_SCENES_DIR))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace tp::host
