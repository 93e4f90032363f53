#pragma once
// A folder of still images played as a video: files sorted by name (numbers inside names
// compared by value, so frame9.png comes before frame10.png), a fixed frame rate, the
// sequence number is the index and the timestamp index / fps.

#include <memory>
#include <string>
#include <vector>

#include "capture/frame_source.hpp"

namespace rostro::capture {

// True when `a` sorts before `b` in natural order ("img2" < "img10"; otherwise by bytes).
bool natural_less(const std::string& a, const std::string& b);

// The image files (by extension: png, jpg, jpeg, bmp, tif, tiff, pgm, ppm, pbm, webp) in
// `folder`, in natural order. Other files are ignored.
std::vector<std::string> list_image_files(const std::string& folder);

// Throws InputError naming the folder when it has no images, or naming the first image
// when it does not decode. fps <= 0 means 25.
std::unique_ptr<FrameSource> open_image_folder_source(const std::string& folder, double fps);

}  // namespace rostro::capture
