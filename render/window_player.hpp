#pragma once
// `rostro play --window`: a FAP stream on the head in a window (render/window_renderer.hpp),
// as the view of play_on_clock(). Keys: Space pauses, Left/Right seek by the player's step,
// Home restarts, Q/Escape quit. The title shows the clock, the frame and whether it is paused.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "facecore/deformer.hpp"
#include "facecore/fap_frame.hpp"
#include "render/camera.hpp"
#include "render/player.hpp"
#include "render/window_renderer.hpp"

namespace rostro::render {

class WindowPlayerView : public PlayerView {
 public:
  // `window` (with the model's mesh set), `deformer` and `stream` must outlive the view.
  WindowPlayerView(WindowRenderer& window, const Deformer& deformer, const FapStream& stream,
                   const CameraPose& pose, const Bounds& framing, std::string title);

  void show(long frame, double clock_s) override;
  std::vector<PlayerCommand> poll() override;
  void wait() override;

 private:
  WindowRenderer& window_;
  const Deformer& deformer_;
  const FapStream& stream_;
  CameraPose pose_;
  Bounds framing_;
  std::string title_;
  bool paused_ = false;
  long shown_ = -1;
  DeformedMesh mesh_;
  std::vector<float> flat_;
  void update_title(double clock_s);
};

}  // namespace rostro::render
