// Cameras through the libcamera C++ API: enumerate, configure one stream, capture with
// mmap'ed frame buffers. Never run against a real camera (none on the build machine);
// enumeration with no camera is tested.
#include "capture/libcamera_source.hpp"

#include <fmt/format.h>
#include <libcamera/libcamera.h>
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <map>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "capture/pixel_convert.hpp"
#include "capture/sequence_counter.hpp"
#include "facecore/error.hpp"

namespace rostro::capture {
namespace {

namespace lc = libcamera;

constexpr auto kFrameTimeout = std::chrono::seconds(5);
constexpr std::size_t kMaxQueuedFrames = 4;

// libcamera allows one CameraManager per process: share one while anything uses it.
std::shared_ptr<lc::CameraManager> shared_camera_manager() {
  static std::mutex mutex;
  static std::weak_ptr<lc::CameraManager> weak;
  const std::lock_guard lock(mutex);
  if (auto manager = weak.lock()) return manager;
  // libcamera logs INFO lines to stderr by default; keep only errors unless the user chose.
  ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
  auto manager =
      std::shared_ptr<lc::CameraManager>(new lc::CameraManager, [](lc::CameraManager* m) {
        m->stop();
        delete m;
      });
  if (const int err = manager->start(); err != 0) {
    throw InputError(fmt::format("libcamera: cannot start the camera manager (error {})", err));
  }
  weak = manager;
  return manager;
}

// Formats rostro converts to BGR, in order of preference (no decode cost first).
const std::vector<lc::PixelFormat>& preferred_formats() {
  static const std::vector<lc::PixelFormat> formats = {lc::formats::RGB888,   lc::formats::BGR888,
                                                       lc::formats::XRGB8888, lc::formats::XBGR8888,
                                                       lc::formats::YUYV,     lc::formats::MJPEG};
  return formats;
}

bool convertible(const lc::PixelFormat& format) {
  const auto& formats = preferred_formats();
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

// Our four-letter names ("MJPG", "YUYV") or libcamera's ("MJPEG", "RGB888").
lc::PixelFormat pixel_format_from_name(const std::string& name) {
  if (name == "MJPG" || name == "JPEG") return lc::formats::MJPEG;
  if (name == "BGR3") return lc::formats::RGB888;  // V4L2's BGR24: B,G,R bytes
  return lc::PixelFormat::fromString(name);
}

void read_frame_rate_limits(const lc::Camera& camera, double& min_fps, double& max_fps) {
  const auto& controls = camera.controls();
  const auto it = controls.find(&lc::controls::FrameDurationLimits);
  if (it == controls.end()) return;
  const auto& min = it->second.min();
  const auto& max = it->second.max();
  if (min.type() != lc::ControlTypeInteger64 || min.isArray() || max.isArray()) return;
  const auto shortest_us = min.get<int64_t>();
  const auto longest_us = max.get<int64_t>();
  if (shortest_us > 0) max_fps = 1e6 / static_cast<double>(shortest_us);
  if (longest_us > 0) min_fps = 1e6 / static_cast<double>(longest_us);
}

std::shared_ptr<lc::Camera> find_camera(lc::CameraManager& manager,
                                        const std::string& id_or_index) {
  const auto cameras = manager.cameras();
  if (!id_or_index.empty() && std::all_of(id_or_index.begin(), id_or_index.end(),
                                          [](char c) { return c >= '0' && c <= '9'; })) {
    const auto index = std::stoul(id_or_index);
    if (index < cameras.size()) return cameras[index];
  }
  if (auto camera = manager.get(id_or_index)) return camera;
  throw InputError(fmt::format(
      "libcamera:{}: no such camera ({} libcamera camera(s) found; 'rostro devices' lists them)",
      id_or_index, cameras.size()));
}

struct PendingFrame {
  cv::Mat image;
  std::int64_t driver_sequence = 0;
  std::uint64_t timestamp_ns = 0;
};

class LibcameraSource final : public FrameSource {
 public:
  LibcameraSource(const std::string& id_or_index, const SourceOptions& options);
  ~LibcameraSource() override;
  LibcameraSource(const LibcameraSource&) = delete;
  LibcameraSource& operator=(const LibcameraSource&) = delete;

  std::optional<Frame> next() override;
  double nominal_fps() const override { return fps_; }
  cv::Size frame_size() const override { return size_; }
  SourceStats stats() const override {
    const std::lock_guard lock(mutex_);
    return stats_;
  }
  std::string description() const override { return description_; }

 private:
  void configure(const SourceOptions& options);
  void map_buffers();
  void start(const SourceOptions& options);
  void on_request_completed(lc::Request* request);
  void on_disconnected();
  cv::Mat convert(const lc::FrameBuffer& buffer) const;

  std::string spec_;
  std::shared_ptr<lc::CameraManager> manager_;
  std::shared_ptr<lc::Camera> camera_;
  bool acquired_ = false;
  bool started_ = false;
  std::unique_ptr<lc::CameraConfiguration> config_;
  lc::Stream* stream_ = nullptr;
  std::unique_ptr<lc::FrameBufferAllocator> allocator_;
  std::vector<std::unique_ptr<lc::Request>> requests_;
  std::map<const lc::FrameBuffer*, std::uint8_t*> mapped_;  // plane 0 address per buffer
  std::vector<std::pair<void*, std::size_t>> mappings_;
  lc::PixelFormat format_;
  unsigned int stride_ = 0;
  cv::Size size_;
  double fps_ = 0;
  std::string description_;

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<PendingFrame> queue_;
  bool disconnected_ = false;
  std::string failure_;
  SequenceCounter sequence_;
  std::optional<std::uint64_t> first_timestamp_ns_;
  SourceStats stats_;
};

LibcameraSource::LibcameraSource(const std::string& id_or_index, const SourceOptions& options)
    : spec_("libcamera:" + id_or_index) {
  manager_ = shared_camera_manager();
  camera_ = find_camera(*manager_, id_or_index);
  if (camera_->acquire() != 0)
    throw InputError(spec_ + ": camera is busy (another program is using it)");
  acquired_ = true;
  camera_->disconnected.connect(this, &LibcameraSource::on_disconnected);
  configure(options);
  map_buffers();
  start(options);
}

void LibcameraSource::configure(const SourceOptions& options) {
  config_ = camera_->generateConfiguration({lc::StreamRole::VideoRecording});
  if (!config_ || config_->size() == 0) throw InputError(spec_ + ": camera offers no video stream");
  lc::StreamConfiguration& stream_config = config_->at(0);
  const lc::StreamFormats& formats = stream_config.formats();
  if (!options.pixel_format.empty()) {
    const lc::PixelFormat wanted = pixel_format_from_name(options.pixel_format);
    if (!wanted.isValid() || !convertible(wanted)) {
      throw InputError(
          spec_ + ": pixel format '" + options.pixel_format +
          "' is not one rostro converts (MJPG, YUYV, RGB888, BGR888, XRGB8888, XBGR8888)");
    }
    stream_config.pixelFormat = wanted;
  } else {
    const auto offered = formats.pixelformats();
    for (const auto& format : preferred_formats()) {
      if (std::find(offered.begin(), offered.end(), format) != offered.end()) {
        stream_config.pixelFormat = format;
        break;
      }
    }
  }
  if (options.width > 0 && options.height > 0) {
    stream_config.size =
        lc::Size(static_cast<unsigned>(options.width), static_cast<unsigned>(options.height));
  }
  stream_config.bufferCount = std::max(stream_config.bufferCount, 4u);
  const auto status = config_->validate();
  if (status == lc::CameraConfiguration::Invalid)
    throw InputError(spec_ + ": camera refused the configuration");
  if (!convertible(stream_config.pixelFormat)) {
    throw InputError(spec_ + ": camera only offers " + stream_config.pixelFormat.toString() +
                     ", which rostro does not convert");
  }
  if ((options.width > 0 && static_cast<int>(stream_config.size.width) != options.width) ||
      (options.height > 0 && static_cast<int>(stream_config.size.height) != options.height) ||
      (!options.pixel_format.empty() &&
       stream_config.pixelFormat != pixel_format_from_name(options.pixel_format))) {
    throw InputError(fmt::format("{}: camera cannot give {} {}x{} (closest: {})", spec_,
                                 options.pixel_format, options.width, options.height,
                                 stream_config.toString()));
  }
  if (camera_->configure(config_.get()) != 0)
    throw InputError(spec_ + ": cannot configure the camera");
  stream_ = stream_config.stream();
  format_ = stream_config.pixelFormat;
  stride_ = stream_config.stride;
  size_ = {static_cast<int>(stream_config.size.width), static_cast<int>(stream_config.size.height)};
}

void LibcameraSource::map_buffers() {
  allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
  if (allocator_->allocate(stream_) < 0)
    throw InputError(spec_ + ": cannot allocate frame buffers");
  for (const auto& buffer : allocator_->buffers(stream_)) {
    // Packed formats use plane 0 only; map the whole dmabuf it lives in.
    const auto& plane = buffer->planes().front();
    std::size_t length = 0;
    for (const auto& p : buffer->planes()) {
      if (p.fd.get() == plane.fd.get())
        length = std::max<std::size_t>(length, std::size_t{p.offset} + p.length);
    }
    void* address = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
    if (address == MAP_FAILED) throw InputError(spec_ + ": cannot map a frame buffer");
    mappings_.emplace_back(address, length);
    mapped_[buffer.get()] = static_cast<std::uint8_t*>(address) + plane.offset;

    auto request = camera_->createRequest();
    if (!request || request->addBuffer(stream_, buffer.get()) != 0) {
      throw InputError(spec_ + ": cannot create a capture request");
    }
    requests_.push_back(std::move(request));
  }
}

void LibcameraSource::start(const SourceOptions& options) {
  lc::ControlList controls(camera_->controls());
  double min_fps = 0, max_fps = 0;
  read_frame_rate_limits(*camera_, min_fps, max_fps);
  fps_ = max_fps > 0 ? std::min(max_fps, 30.0) : 30.0;
  if (options.fps > 0) {
    if (max_fps > 0 && (options.fps > max_fps * 1.01 || options.fps < min_fps * 0.99)) {
      throw InputError(fmt::format("{}: {:g} fps is outside the camera's range {:.1f}..{:.1f}",
                                   spec_, options.fps, min_fps, max_fps));
    }
    fps_ = options.fps;
  }
  const auto frame_us = static_cast<int64_t>(std::llround(1e6 / fps_));
  const int64_t limits[2] = {frame_us, frame_us};
  controls.set(lc::controls::FrameDurationLimits, lc::Span<const int64_t, 2>(limits));
  if (options.exposure) {
    controls.set(lc::controls::AeEnable, false);
    controls.set(lc::controls::ExposureTime,
                 static_cast<int32_t>(std::lround(*options.exposure * 100.0)));
  }
  if (options.gain) {
    controls.set(lc::controls::AeEnable, false);
    controls.set(lc::controls::AnalogueGain, static_cast<float>(*options.gain));
  }
  camera_->requestCompleted.connect(this, &LibcameraSource::on_request_completed);
  if (camera_->start(&controls) != 0) throw InputError(spec_ + ": cannot start the camera");
  started_ = true;
  for (auto& request : requests_) {
    if (camera_->queueRequest(request.get()) != 0)
      throw InputError(spec_ + ": cannot queue a capture request");
  }
  description_ = fmt::format("libcamera {} {} {}x{} @ {:g} fps", camera_->id(), format_.toString(),
                             size_.width, size_.height, fps_);
}

LibcameraSource::~LibcameraSource() {
  if (camera_) {
    if (started_) camera_->stop();
    camera_->requestCompleted.disconnect(this);
    camera_->disconnected.disconnect(this);
  }
  requests_.clear();
  if (allocator_ && stream_) allocator_->free(stream_);
  for (auto& [address, length] : mappings_) ::munmap(address, length);
  allocator_.reset();
  if (acquired_) camera_->release();
  camera_.reset();
}

cv::Mat LibcameraSource::convert(const lc::FrameBuffer& buffer) const {
  const auto it = mapped_.find(&buffer);
  if (it == mapped_.end() || buffer.metadata().planes().size() == 0) return {};
  std::uint8_t* data = it->second;
  const std::size_t used = buffer.metadata().planes()[0].bytesused;
  const int w = size_.width, h = size_.height;
  if (format_ == lc::formats::MJPEG) return decode_mjpeg(data, used);
  if (format_ == lc::formats::YUYV) return yuyv_to_bgr(data, used, w, h, stride_);
  const int channels =
      (format_ == lc::formats::XRGB8888 || format_ == lc::formats::XBGR8888) ? 4 : 3;
  if (used < std::size_t{stride_} * static_cast<std::size_t>(h - 1) +
                 static_cast<std::size_t>(w * channels))
    return {};
  const cv::Mat view(h, w, channels == 4 ? CV_8UC4 : CV_8UC3, data, stride_);
  cv::Mat bgr;
  // libcamera names follow DRM: RGB888 is stored B,G,R in memory, BGR888 is R,G,B.
  if (format_ == lc::formats::RGB888)
    bgr = view.clone();
  else if (format_ == lc::formats::BGR888)
    cv::cvtColor(view, bgr, cv::COLOR_RGB2BGR);
  else if (format_ == lc::formats::XRGB8888)
    cv::cvtColor(view, bgr, cv::COLOR_BGRA2BGR);
  else
    cv::cvtColor(view, bgr, cv::COLOR_RGBA2BGR);
  return bgr;
}

// Runs on libcamera's thread: copy the frame out, give the buffer straight back.
void LibcameraSource::on_request_completed(lc::Request* request) {
  if (request->status() == lc::Request::RequestCancelled) return;
  const lc::FrameBuffer* buffer = request->findBuffer(stream_);
  PendingFrame pending;
  if (buffer && buffer->metadata().status == lc::FrameMetadata::FrameSuccess) {
    pending.image = convert(*buffer);
    pending.driver_sequence = buffer->metadata().sequence;
    pending.timestamp_ns = buffer->metadata().timestamp;
  }
  request->reuse(lc::Request::ReuseBuffers);
  camera_->queueRequest(request);
  if (pending.image.empty()) return;  // the gap in sequence numbers counts it as dropped
  {
    const std::lock_guard lock(mutex_);
    // A consumer that falls behind loses the oldest frames; the sequence gap shows it.
    if (queue_.size() >= kMaxQueuedFrames) queue_.pop_front();
    queue_.push_back(std::move(pending));
  }
  ready_.notify_one();
}

void LibcameraSource::on_disconnected() {
  {
    const std::lock_guard lock(mutex_);
    disconnected_ = true;
  }
  ready_.notify_all();
}

std::optional<Frame> LibcameraSource::next() {
  std::unique_lock lock(mutex_);
  if (!failure_.empty()) throw InputError(failure_);
  if (!ready_.wait_for(lock, kFrameTimeout, [&] { return !queue_.empty() || disconnected_; })) {
    failure_ =
        fmt::format("{}: no frame for {} s after {} frames (frames already captured are kept)",
                    spec_, kFrameTimeout.count(), stats_.delivered);
    throw InputError(failure_);
  }
  if (queue_.empty()) {
    failure_ =
        fmt::format("{}: camera was unplugged after {} frames (frames already captured are kept)",
                    spec_, stats_.delivered);
    throw InputError(failure_);
  }
  PendingFrame pending = std::move(queue_.front());
  queue_.pop_front();
  sequence_.observe(pending.driver_sequence);
  if (!first_timestamp_ns_) first_timestamp_ns_ = pending.timestamp_ns;
  Frame frame;
  frame.image = std::move(pending.image);
  frame.sequence = sequence_.relative();
  frame.timestamp_s = static_cast<double>(pending.timestamp_ns - *first_timestamp_ns_) * 1e-9;
  stats_.delivered += 1;
  stats_.dropped = sequence_.dropped();
  return frame;
}

}  // namespace

bool libcamera_built() {
  return true;
}

std::vector<LibcameraCameraInfo> list_libcamera_cameras() {
  const auto manager = shared_camera_manager();
  std::vector<LibcameraCameraInfo> list;
  for (const auto& camera : manager->cameras()) {
    LibcameraCameraInfo info;
    info.id = camera->id();
    const auto& properties = camera->properties();
    if (const auto model = properties.get(lc::properties::Model)) info.model = *model;
    if (const auto location = properties.get(lc::properties::Location)) {
      info.location = *location == lc::properties::CameraLocationFront  ? "front"
                      : *location == lc::properties::CameraLocationBack ? "back"
                                                                        : "external";
    }
    read_frame_rate_limits(*camera, info.min_fps, info.max_fps);
    if (const auto config = camera->generateConfiguration({lc::StreamRole::VideoRecording});
        config && config->size() > 0) {
      const auto& formats = config->at(0).formats();
      for (const auto& format : formats.pixelformats()) {
        for (const auto& size : formats.sizes(format)) {
          info.modes.push_back(
              {format.toString(), static_cast<int>(size.width), static_cast<int>(size.height)});
        }
      }
    }
    list.push_back(std::move(info));
  }
  return list;
}

std::unique_ptr<FrameSource> open_libcamera_source(const std::string& id_or_index,
                                                   const SourceOptions& options) {
  return std::make_unique<LibcameraSource>(id_or_index, options);
}

}  // namespace rostro::capture
