#include "eval/truth_tracks.hpp"

#include "facecore/error.hpp"
#include "tracking/tracks_csv.hpp"

namespace rostro::eval {

bool is_pts_truth(const std::filesystem::path& path) {
  const auto ext = path.extension();
  return std::filesystem::is_directory(path) || ext == ".pts" || ext == ".txt" || ext == ".lst";
}

std::vector<tracking::TrackedFrame> read_truth_tracks(const std::filesystem::path& path,
                                                      const TruthOptions& options) {
  if (!std::filesystem::exists(path)) throw InputError(path.string() + ": no such file or folder");
  if (!is_pts_truth(path)) return tracking::read_tracks(path);
  const IbugMapping mapping =
      options.pts_mapping.empty() ? default_ibug_mapping() : read_ibug_mapping(options.pts_mapping);
  const std::vector<std::filesystem::path> files = path.extension() == ".pts"
                                                       ? std::vector<std::filesystem::path>{path}
                                                       : list_pts_sequence(path);
  return read_pts_sequence(files, mapping, options.pts_first_frame, options.pts_fps);
}

}  // namespace rostro::eval
