#include "render/window_player.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <utility>

#include "render/face_renderer.hpp"

namespace rostro::render {
namespace {

constexpr std::pair<WindowKey, PlayerCommand> kCommands[] = {
    {WindowKey::Space, PlayerCommand::TogglePause},
    {WindowKey::Left, PlayerCommand::SeekBack},
    {WindowKey::Right, PlayerCommand::SeekForward},
    {WindowKey::Home, PlayerCommand::Restart},
    {WindowKey::Quit, PlayerCommand::Quit}};

}  // namespace

WindowPlayerView::WindowPlayerView(WindowRenderer& window, const Deformer& deformer,
                                   const FapStream& stream, const CameraPose& pose,
                                   const Bounds& framing, std::string title)
    : window_(window),
      deformer_(deformer),
      stream_(stream),
      pose_(pose),
      framing_(framing),
      title_(std::move(title)) {}

void WindowPlayerView::show(long frame, double clock_s) {
  deformer_.deform(stream_.frames[static_cast<std::size_t>(frame)], mesh_);
  flatten(mesh_.positions(), flat_);
  window_.update_positions(flat_);
  window_.draw(pose_, framing_);
  shown_ = frame;
  update_title(clock_s);
}

std::vector<PlayerCommand> WindowPlayerView::poll() {
  window_.poll();
  std::vector<PlayerCommand> commands;
  for (const WindowKey key : window_.take_keys()) {
    for (const auto& [k, command] : kCommands) {
      if (k == key) commands.push_back(command);
    }
    // The player shows the frame at the paused (or resumed) clock next, with this title.
    if (key == WindowKey::Space) paused_ = !paused_;
  }
  if (window_.should_close() && (commands.empty() || commands.back() != PlayerCommand::Quit))
    commands.push_back(PlayerCommand::Quit);
  return commands;
}

void WindowPlayerView::wait() {
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

void WindowPlayerView::update_title(double clock_s) {
  char text[160];
  std::snprintf(text, sizeof text,
                "  %.2f s  frame %ld/%zu%s   [Space] pause  [Left/Right] seek  [Q] quit", clock_s,
                shown_, stream_.frames.size(), paused_ ? "  (paused)" : "");
  window_.set_title(title_ + text);
}

}  // namespace rostro::render
