#include "render/fap_editor.hpp"

// glcorearb.h first: GLFW then leaves the OpenGL headers alone.
#include "render/gl_api.hpp"
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "facecore/deformer.hpp"
#include "facecore/error.hpp"
#include "facecore/fap_io.hpp"
#include "facecore/fap_table.hpp"
#include "render/face_renderer.hpp"
#include "render/frame_sink.hpp"
#include "render/window_renderer.hpp"

namespace rostro::render {
namespace {

constexpr int kEntryCount = kExpressionCount + kVisemeCount;
constexpr int kPanelWidth = 460;  // the sliders' panel on the left; the head is on the right

// The MPEG-4 FAP groups 2..10 (group 1 is the high-level FAPs 1 and 2).
constexpr std::array<const char*, 11> kGroupNames = {"",
                                                     "visemes and expressions",
                                                     "jaw, chin, inner lips, corners",
                                                     "eyes: eyeballs, pupils, eyelids",
                                                     "eyebrows",
                                                     "cheeks",
                                                     "tongue",
                                                     "head rotation",
                                                     "outer lips",
                                                     "nose",
                                                     "ears"};

std::string entry_label(int entry) {
  if (entry < kExpressionCount) return std::string(ExpressionLibrary::expression_name(entry));
  return "viseme " + std::string(ExpressionLibrary::viseme_name(entry - kExpressionCount));
}

const FapFrame& entry_faps(const ExpressionLibrary& library, int entry) {
  return entry < kExpressionCount ? library.expression(entry)
                                  : library.viseme(entry - kExpressionCount);
}

void set_entry_faps(ExpressionLibrary& library, int entry, const FapFrame& faps) {
  if (entry < kExpressionCount)
    library.set_expression(entry, faps);
  else
    library.set_viseme(entry - kExpressionCount, faps);
}

// A slider's range: rotations (AU, 1e-5 rad) span a quarter turn, distances 1000 FAPU.
float fap_range(int id) {
  return fap_info(id).unit == FapUnit::AU ? 157080.f : 1000.f;
}

// The editor's state between frames.
struct Editor {
  const EditorOptions& options;
  ExpressionLibrary& library;
  int entry = 0;
  int selected = 0;  // the FAP PageUp/PageDown nudge; 0: none
  bool unsaved = false;
  CameraPose camera;
  // Preview of the high-level FAPs over the entry: FAP 2 and FAP 1 (0 = off).
  int preview_expression = 0;
  int preview_intensity = 63;
  int preview_viseme = 0;
  bool export_requested = false;  // read the head back after the next draw, then export
  std::string status;

  void set_value(int id, double value) {
    FapFrame faps = entry_faps(library, entry);
    if (value == 0.0)
      faps.clear(id);
    else
      faps.set(id, value);
    set_entry_faps(library, entry, faps);
    unsaved = true;
  }
  void note(const std::string& text) {
    status = text;
    if (options.log) options.log(text);
  }
  void save() {
    try {
      library.save(options.expressions, options.visemes);
      unsaved = false;
      note("saved " + options.expressions.string() + " and " + options.visemes.string());
    } catch (const InputError& e) {
      note(std::string("not saved: ") + e.what());
    }
  }
  // The frame drawn: the entry's FAPs, with the preview's FAPs 1 and 2 on top.
  FapFrame shown() const {
    FapFrame frame = entry_faps(library, entry);
    if (preview_expression > 0) {
      ExpressionParams e;
      e.select1 = preview_expression;
      e.intensity1 = preview_intensity;
      frame.set_expression(e);
    }
    if (preview_viseme > 0) {
      VisemeParams v;
      v.select1 = v.select2 = preview_viseme;
      v.blend = 63;
      frame.set_viseme(v);
    }
    return frame;
  }
  void panel();
  void export_pose(const cv::Mat& image);
};

void Editor::export_pose(const cv::Mat& image) {
  FapStream stream;
  stream.header.name = "rostro-edit";
  stream.header.fps = 25;
  stream.frames.push_back(shown());
  const std::filesystem::path fap = options.export_prefix.string() + ".fap";
  const std::filesystem::path png = options.export_prefix.string() + ".png";
  try {
    write_fap_stream(fap, stream);
    write_image(png, image);
    note("exported " + fap.string() + " and " + png.string());
  } catch (const std::exception& e) {
    note(std::string("not exported: ") + e.what());
  }
}

void Editor::panel() {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, ImGui::GetIO().DisplaySize.y));
  // The scrollbar's place is kept even while the open sections fit: the panel is about as tall
  // as the window, and a scrollbar that came and went with a few pixels of overflow (from the
  // first frame to the next, or as a section opens) narrowed every slider under the pointer.
  ImGui::Begin("rostro edit", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_AlwaysVerticalScrollbar);
  if (ImGui::BeginCombo("entry", entry_label(entry).c_str())) {
    for (int i = 0; i < kEntryCount; ++i)
      if (ImGui::Selectable(entry_label(i).c_str(), i == entry)) entry = i;
    ImGui::EndCombo();
  }
  if (ImGui::Button("Save libraries (Ctrl+S)")) save();
  ImGui::SameLine();
  if (ImGui::Button("Export pose .fap/.png")) export_requested = true;
  ImGui::TextWrapped("%s%s", unsaved ? "unsaved edits. " : "", status.c_str());
  ImGui::TextWrapped("selected (PageUp/PageDown): %s",
                     selected ? std::string(fap_info(selected).name).c_str() : "none");
  if (ImGui::CollapsingHeader("camera and FAP 1/FAP 2 preview")) {
    float yaw = static_cast<float>(camera.yaw_deg), pitch = static_cast<float>(camera.pitch_deg);
    if (ImGui::SliderFloat("yaw", &yaw, -90, 90, "%.0f deg")) camera.yaw_deg = yaw;
    if (ImGui::SliderFloat("pitch", &pitch, -60, 60, "%.0f deg")) camera.pitch_deg = pitch;
    ImGui::SliderInt("FAP 2 expression", &preview_expression, 0, kExpressionCount - 1,
                     std::string(ExpressionLibrary::expression_name(preview_expression)).c_str());
    ImGui::SliderInt("FAP 2 intensity", &preview_intensity, 0, 63);
    ImGui::SliderInt("FAP 1 viseme", &preview_viseme, 0, kVisemeCount - 1,
                     std::string(ExpressionLibrary::viseme_name(preview_viseme)).c_str());
    if (ImGui::Button("Copy the preview into this entry")) {
      const FapFrame expanded = library.expand(shown());
      set_entry_faps(library, entry, expanded);
      preview_expression = preview_viseme = 0;
      unsaved = true;
    }
  }
  const FapFrame faps = entry_faps(library, entry);
  ImGui::PushItemWidth(-180);  // room for the longest FAP name
  for (int group = 2; group <= 10; ++group) {
    const bool open = ImGui::CollapsingHeader(
        kGroupNames[static_cast<std::size_t>(group)],
        group == 2 || group == 8 || group == 4 ? ImGuiTreeNodeFlags_DefaultOpen : 0);
    if (!open) continue;
    for (const FapInfo& fap : fap_table()) {
      if (fap.group != group) continue;
      float value = static_cast<float>(faps.get(fap.id));
      const float range = fap_range(fap.id);
      ImGui::PushID(fap.id);
      if (fap.id == selected) ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 210, 90, 255));
      if (ImGui::SliderFloat(std::string(fap.name).c_str(), &value, -range, range, "%.0f"))
        set_value(fap.id, std::round(value));
      if (fap.id == selected) ImGui::PopStyleColor();
      if (ImGui::IsItemActivated()) selected = fap.id;
      ImGui::PopID();
    }
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace

int editor_entry(const std::string& name) {
  for (int i = 0; i < kEntryCount; ++i) {
    if (entry_label(i) == name) return i;
    if (i >= kExpressionCount && ExpressionLibrary::viseme_name(i - kExpressionCount) == name)
      return i;
  }
  std::string names;
  for (int i = 0; i < kEntryCount; ++i) names += (i ? ", " : "") + entry_label(i);
  throw InputError("entry '" + name + "': expected one of " + names);
}

bool run_fap_editor(const FaceModel& model, ExpressionLibrary& library,
                    const EditorOptions& options) {
  Editor editor{options, library, 0, 0, false, options.camera, 0, 63, 0, false, {}};
  editor.entry = editor_entry(options.entry);
  if (!options.select.empty()) {
    const auto id = find_fap(options.select);
    if (!id || *id <= kExpressionFap)
      throw InputError("--select '" + options.select + "': expected a low-level FAP name");
    editor.selected = *id;
  }

  WindowOptions wo;
  wo.width = options.width;
  wo.height = options.height;
  wo.title = "rostro edit";
  wo.no_display = "no display for the editor";
  wo.vsync = true;
  WindowRenderer window(wo);
  window.set_mesh(to_render_mesh(model));
  const Bounds framing = portrait_bounds(model, window.mesh_bounds());
  const Deformer deformer(model, &library);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window.glfw_window(), true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  std::vector<Eigen::Vector3f> positions;
  std::vector<float> flat;
  while (!window.should_close()) {
    window.poll();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGuiIO& io = ImGui::GetIO();
    // The window queues every press (ImGui 1.86 sees only keys held at a frame's start).
    for (const WindowKey key : window.take_keys()) {
      if (key == WindowKey::Save) editor.save();
      if ((key != WindowKey::PageUp && key != WindowKey::PageDown) || io.WantTextInput ||
          editor.selected == 0)
        continue;
      const double step = (key == WindowKey::PageUp ? 1 : -1) * fap_range(editor.selected) / 50.0;
      const double v = entry_faps(library, editor.entry).get(editor.selected);
      editor.set_value(editor.selected, std::round(v + step));
    }
    if (!io.WantCaptureMouse && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
      editor.camera.yaw_deg =
          std::clamp(editor.camera.yaw_deg - io.MouseDelta.x * 0.3, -90.0, 90.0);
      editor.camera.pitch_deg =
          std::clamp(editor.camera.pitch_deg + io.MouseDelta.y * 0.3, -60.0, 60.0);
    }
    editor.panel();

    int width = 0, height = 0;
    window.framebuffer_size(width, height);
    const int panel = std::min(width, kPanelWidth);
    deformer.deform(editor.shown(), positions);
    flatten(positions, flat);
    window.update_positions(flat);
    window.draw_into(editor.camera, framing, panel, 0, width - panel, height);
    if (editor.export_requested && width - panel > 0 && height > 0) {
      cv::Mat head(height, width - panel, CV_8UC3);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(panel, 0, width - panel, height, GL_BGR, GL_UNSIGNED_BYTE, head.data);
      cv::flip(head, head, 0);  // OpenGL's row 0 is the bottom
      editor.export_pose(head);
    }
    editor.export_requested = false;
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    window.present();
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  return editor.unsaved;
}

}  // namespace rostro::render
