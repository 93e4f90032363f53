#include "render/video_writer.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "facecore/error.hpp"

extern char** environ;

namespace rostro::render {
namespace fs = std::filesystem;
namespace {

std::atomic<int> temp_counter{0};

std::string number(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

}  // namespace

VideoWriter::VideoWriter(fs::path destination, VideoOptions options)
    : destination_(std::move(destination)), options_(std::move(options)) {
  if (!(options_.fps > 0.0) || options_.fps > 1000.0) {
    throw InputError(destination_.string() + ": frame rate " + number(options_.fps) +
                     " is outside (0, 1000]");
  }
  std::error_code ec;
  if (!options_.audio.empty() && !fs::is_regular_file(options_.audio, ec)) {
    throw InputError(options_.audio.string() + ": no such audio file");
  }
  const fs::path parent =
      destination_.has_parent_path() ? destination_.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec)) {
    throw InputError(destination_.string() + ": the folder " + parent.string() + " does not exist");
  }
  if (fs::is_directory(destination_, ec)) {
    throw InputError(destination_.string() + ": is a folder, expected a video file name");
  }
  std::string stem = ".";  // hidden, and built by appends (GCC 12 misreports "." + string)
  stem.append(destination_.filename().string())
      .append(".partial-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(temp_counter++));
  // The temporary keeps the destination's extension: ffmpeg picks the container from it.
  temporary_ = parent / (stem + destination_.extension().string());
  log_ = parent / (stem + ".log");
  if (const char* program = std::getenv("ROSTRO_FFMPEG"); program && *program) {
    options_.ffmpeg = program;
  }
}

VideoWriter::~VideoWriter() {
  if (!finished_) abandon();
}

void VideoWriter::start(cv::Size size) {
  std::vector<std::string> args = {options_.ffmpeg,
                                   "-hide_banner",
                                   "-loglevel",
                                   "error",
                                   "-y",
                                   "-f",
                                   "rawvideo",
                                   "-pix_fmt",
                                   "bgr24",
                                   "-video_size",
                                   std::to_string(size.width) + "x" + std::to_string(size.height),
                                   "-framerate",
                                   number(options_.fps),
                                   "-i",
                                   "pipe:0"};
  if (!options_.audio.empty()) {
    args.insert(args.end(), {"-i", options_.audio.string()});
  }
  args.insert(args.end(), {"-map", "0:v:0"});
  if (!options_.audio.empty()) args.insert(args.end(), {"-map", "1:a:0"});
  // yuv420p (what every player decodes) needs even sizes: pad odd ones by a pixel.
  args.insert(args.end(), {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset",
                           options_.preset, "-crf", std::to_string(options_.crf), "-pix_fmt",
                           "yuv420p", "-r", number(options_.fps)});
  if (!options_.audio.empty()) args.insert(args.end(), {"-c:a", "aac", "-b:a", "160k"});
  args.insert(args.end(), {"-movflags", "+faststart", temporary_.string()});

  // A socket rather than a pipe: send(MSG_NOSIGNAL) reports a dead ffmpeg as an error
  // instead of killing the whole program with SIGPIPE, without touching signal handlers.
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    throw std::system_error(errno, std::generic_category(), "socketpair for ffmpeg");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log_.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc =
      posix_spawnp(&pid, options_.ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    std::error_code ec;
    fs::remove(log_, ec);
    throw InputError("cannot run '" + options_.ffmpeg + "' to encode " + destination_.string() +
                     " (" + std::strerror(rc) + "); install ffmpeg or write PNG frames instead");
  }
  pid_ = pid;
  pipe_fd_ = fds[0];
  size_ = size;
}

void VideoWriter::write(const cv::Mat& bgr) {
  if (finished_) throw std::logic_error("VideoWriter::write after finish");
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw std::invalid_argument("video writer: frames must be 8-bit BGR images");
  }
  if (pid_ < 0) start(bgr.size());
  if (bgr.size() != size_) {
    throw std::invalid_argument("video writer: frame of " + std::to_string(bgr.cols) + "x" +
                                std::to_string(bgr.rows) + " in a video of " +
                                std::to_string(size_.width) + "x" + std::to_string(size_.height));
  }
  const cv::Mat packed = bgr.isContinuous() ? bgr : bgr.clone();
  const auto* data = packed.ptr<const char>();
  std::size_t left = packed.total() * packed.elemSize();
  while (left > 0) {
    const ssize_t sent = ::send(pipe_fd_, data, left, MSG_NOSIGNAL);
    if (sent < 0) {
      if (errno == EINTR) continue;
      const std::string message = ffmpeg_message();
      abandon();
      throw InputError(destination_.string() + ": ffmpeg stopped at frame " +
                       std::to_string(count_) + (message.empty() ? "" : ": " + message));
    }
    data += sent;
    left -= static_cast<std::size_t>(sent);
  }
  ++count_;
}

int VideoWriter::wait_for_ffmpeg() {
  if (pipe_fd_ >= 0) {
    ::close(pipe_fd_);  // end of input: ffmpeg flushes and writes the index
    pipe_fd_ = -1;
  }
  int status = 0;
  if (pid_ > 0) {
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
  return status;
}

std::string VideoWriter::ffmpeg_message() const {
  std::ifstream in(log_);
  std::string line;
  std::string last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last;
}

void VideoWriter::finish() {
  if (finished_) return;
  if (count_ == 0) {
    abandon();
    throw InputError(destination_.string() + ": no frames to write");
  }
  const int status = wait_for_ffmpeg();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string message = ffmpeg_message();
    abandon();
    throw InputError(destination_.string() + ": ffmpeg failed" +
                     (message.empty() ? "" : ": " + message));
  }
  std::error_code ec;
  fs::rename(temporary_, destination_, ec);
  if (ec) {
    abandon();
    throw InputError(destination_.string() + ": cannot move the video into place (" + ec.message() +
                     ")");
  }
  fs::remove(log_, ec);
  finished_ = true;
}

void VideoWriter::abandon() noexcept {
  if (pid_ > 0) ::kill(pid_, SIGTERM);
  wait_for_ffmpeg();
  std::error_code ec;
  fs::remove(temporary_, ec);
  fs::remove(log_, ec);
  finished_ = true;
}

}  // namespace rostro::render
