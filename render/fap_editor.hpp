#pragma once
// `rostro edit`: an interactive editor of the expression and viseme libraries (Dear ImGui
// over the head in one window). Each of the 22 entries (neutral, the six expressions, the
// 15 visemes) is a set of low-level FAP values edited with a slider per FAP, grouped as in
// MPEG-4 (jaw and inner lips, eyes, brows, cheeks, tongue, head, outer lips, nose, ears);
// the head follows every change, seen by a camera that orbits with a mouse drag. A preview
// of FAP 2 (an expression at an intensity) and FAP 1 (a viseme) shows the library's
// high-level FAPs on top. Keys: PageUp/PageDown nudge the selected FAP (the last slider
// touched, or EditorOptions::select), Ctrl+S saves both libraries, Escape quits.

#include <filesystem>
#include <functional>
#include <string>

#include "facecore/expression_library.hpp"
#include "facecore/face_model.hpp"
#include "render/camera.hpp"

namespace rostro::render {

struct EditorOptions {
  std::filesystem::path expressions;  // read by the caller, written by Ctrl+S / "Save"
  std::filesystem::path visemes;
  std::string entry = "neutral";  // the entry edited first: "joy", "viseme aa", "aa", ...
  std::string select;             // the FAP PageUp/PageDown nudge first ("open_jaw")
  std::filesystem::path export_prefix = "pose";  // "Export" writes PREFIX.fap and PREFIX.png
  int width = 1280;
  int height = 800;
  CameraPose camera;
  std::function<void(const std::string&)> log;  // what was saved or exported
};

// Which entry `name` names: 0..6 an expression, 7..21 viseme (index + 7); throws InputError
// listing the names otherwise.
int editor_entry(const std::string& name);

// Runs the editor until the window closes. Returns true if edits were left unsaved. Throws
// RenderUnavailable without a display, InputError for an unknown entry or FAP name.
bool run_fap_editor(const FaceModel& model, ExpressionLibrary& library,
                    const EditorOptions& options);

}  // namespace rostro::render
