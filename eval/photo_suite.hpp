#pragma once
// `rostro eval photos`: the photo scenes (eval/photo_scene.hpp) of data/eval/photo_scenes.json,
// each tracked frame by frame as it is rendered by the marker tracker with automatic
// identification, and scored against its exact truth.
//
// photo_scenes.json:
//   { "description": ..., "seconds": 5, "fps": 25, "size": [1280, 720], "noise": 2,
//     "scenarios": [ { "name": "turns_a", "title": "...", "photo": "2008_001009.jpg",
//                      "face_px": 300, "dot_px": 8, "motion": "turns" }, ... ] }
// Scenario keys (each optional but name and photo): title, photo (relative to the fixtures
// folder), face, size [w, h], face_px, dot_px, fps, seconds, motion, first_blur_px,
// enter_seconds, brightness, gradient, noise, hand (true/false), seed, placement_jitter:
// PhotoSceneOptions' fields of the same names. The top-level seconds, fps, size, noise and
// placement_jitter are defaults.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "eval/photo_scene.hpp"
#include "eval/suite.hpp"
#include "tracking/marker_tracker.hpp"

namespace rostro::eval {

struct PhotoScenario {
  std::string name, title;
  PhotoSceneOptions scene;  // scene.photo relative to the fixtures folder
};

struct PhotoSuiteDefinition {
  std::string description;
  std::vector<PhotoScenario> scenarios;
};

// Throws InputError naming the file and the scenario or key at fault.
PhotoSuiteDefinition load_photo_scenes(const std::filesystem::path& path);
// data/eval/photo_scenes.json
std::filesystem::path default_photo_scenes_path();
// $ROSTRO_SHARED/fixtures/faces, else ../shared/fixtures/faces beside the repository.
std::filesystem::path default_faces_dir();

struct PhotoRow {
  SuiteRow suite;  // the suite's columns (eval/suite.hpp)
  // Observations valid in the estimate while the marker is not visible in the truth (under the
  // hand, outside the frame).
  long hidden_reported = 0;
  // The most frames any marker took, after coming back into view from an occlusion (hidden in
  // the truth after having been visible), to be valid in the estimate within 2 px of its
  // truth; -1 when one never came back before it was hidden again or the take ended; 0 when
  // every one was back on its first visible frame or there was no such occlusion.
  long worst_reacquire = 0;
  long occlusions = 0;  // such returns into view counted
};

// Renders and tracks one scenario with `layout`; `faces` is the folder its photo is in. Each
// rendered frame also goes to `frames` when given (a video of the scene).
PhotoRow run_photo_scenario(const PhotoScenario& scenario, const std::filesystem::path& faces,
                            const tracking::MarkerLayout& layout,
                            const std::function<void(long, long)>& progress = {},
                            const tracking::TrackerOptions& tracker_options = {},
                            const PhotoFrameSink& frames = {});

// Hidden-but-reported and reacquisition (PhotoRow's fields) from a truth and an estimate with
// the same frames and markers in the same order.
void count_hidden_and_reacquire(const std::vector<tracking::TrackedFrame>& truth,
                                const std::vector<tracking::TrackedFrame>& estimate, PhotoRow& row);

// Per scene: dot centre error median and 95th percentile (px, over scored observations),
// swaps (events), lost observations, hidden but reported, worst frames to reacquire.
std::string photo_table_markdown(const std::vector<PhotoRow>& rows);
std::string photo_table_text(const std::vector<PhotoRow>& rows);

}  // namespace rostro::eval
