#pragma once
// Draws what the tracker knows onto a frame, for the overlay video of `rostro track`: each
// marker's id at its position, green when valid, and a red ring with "lost" where it was
// last seen when it is not.

#include <opencv2/core.hpp>
#include <vector>

#include "tracking/marker_tracker.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::tracking {

// `image` is 8-bit BGR (grey images are converted in place).
void draw_overlay(cv::Mat& image, const std::vector<MarkerState>& states, long frame);

// The same from a tracked frame alone (no tracker at hand, as in `rostro live`'s view):
// a green cross where a marker is valid, a red ring where it is not.
void draw_tracked_frame(cv::Mat& image, const TrackedFrame& frame);

}  // namespace rostro::tracking
