#pragma once
// Storyboards written to a scratch folder, and the default libraries a scene needs.

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "facecore/expression_library.hpp"
#include "script/scene.hpp"
#include "script/storyboard_reader.hpp"
#include "speech/behaviour.hpp"
#include "speech/key_shapes.hpp"

namespace rostro::script::test {

// An empty folder of its own under the system's temporary folder.
inline std::filesystem::path scratch(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("rostro-script-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path write(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path;
}

// A storyboard file `name` holding `body`, alone in a new scratch folder `folder`.
inline std::filesystem::path story(const std::string& folder, const std::string& name,
                                   const std::string& body) {
  return write(scratch(folder) / name, body);
}

// The libraries, loaded once per test, and a scene built from a storyboard file.
struct Defaults {
  ExpressionLibrary library = ExpressionLibrary::load_default();
  speech::KeyShapes shapes = speech::KeyShapes::load_default(library);
  speech::BehaviourSettings behaviour = speech::BehaviourSettings::load_default();

  std::unique_ptr<Scene> scene(const Storyboard& board) const {
    std::vector<std::string> warnings;
    SceneOptions options;
    options.fps = board.fps;
    options.seed = board.seed;
    return std::make_unique<Scene>(board, resolve_speech(board, behaviour, warnings), library,
                                   shapes, behaviour, options);
  }
  std::unique_ptr<Scene> scene(const std::filesystem::path& story) const {
    return scene(read_storyboard(story, 1));
  }
};

}  // namespace rostro::script::test
