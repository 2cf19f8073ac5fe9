// The error a reader gives for a text, for the tests of the readers' limits and of hostile input.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "host/meshes.hpp"
#include "host/scene.hpp"

namespace tp::host::test {

// The message of the MeshError parse_obj throws for `text` ("" if it loads).
inline std::string obj_error(const std::string& text, const std::string& file) {
  try {
    parse_obj(text, file);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

// The SceneError parse_scene throws for `text` (meshes relative to the test data); a failure if
// the scene loads.
inline SceneError scene_error(const std::string& text, const std::string& file) {
  try {
    parse_scene(text, file, TP_HOST_TEST_DATA);
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "the scene loaded";
  return SceneError("", -1, "", "");
}

}  // namespace tp::host::test
