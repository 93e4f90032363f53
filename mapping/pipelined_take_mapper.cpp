#include "mapping/pipelined_take_mapper.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace rostro::mapping {

PipelinedTakeMapper::PipelinedTakeMapper(const tracking::MarkerLayout& layout,
                                         MapperOptions options,
                                         const calib::CameraIntrinsics& camera,
                                         std::optional<calib::ActorProfile> profile,
                                         long calibration_frames, long max_queued)
    : take_(layout, std::move(options), camera, std::move(profile), calibration_frames),
      max_queued_(static_cast<std::size_t>(std::max(1L, max_queued))),
      worker_([this] { run(); }) {}

PipelinedTakeMapper::~PipelinedTakeMapper() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  work_.notify_one();
  worker_.join();
}

std::vector<FapFrame> PipelinedTakeMapper::push(tracking::TrackedFrame frame) {
  std::unique_lock lock(mutex_);
  if (finishing_) throw std::logic_error("PipelinedTakeMapper::push after finish()");
  changed_.wait(lock, [&] { return queue_.size() < max_queued_ || done_; });
  if (error_) std::rethrow_exception(error_);
  queue_.push_back(std::move(frame));
  ++pushed_;
  work_.notify_one();
  std::vector<FapFrame> out;
  out.swap(ready_);
  returned_ += static_cast<long>(out.size());
  return out;
}

std::vector<FapFrame> PipelinedTakeMapper::finish() {
  std::unique_lock lock(mutex_);
  finishing_ = true;
  work_.notify_one();
  changed_.wait(lock, [&] { return done_; });
  if (error_) std::rethrow_exception(error_);
  std::vector<FapFrame> out;
  out.swap(ready_);
  returned_ += static_cast<long>(out.size());
  return out;
}

long PipelinedTakeMapper::held_back() const {
  const std::lock_guard lock(mutex_);
  return pushed_ - returned_;
}

std::optional<calib::NeutralMotion> PipelinedTakeMapper::calibration_motion() const {
  const std::lock_guard lock(mutex_);
  return calibration_motion_;
}

bool PipelinedTakeMapper::self_calibrated() const {
  return calibration_frames_used() > 0;
}

long PipelinedTakeMapper::calibration_frames_used() const {
  const std::lock_guard lock(mutex_);
  return calibration_frames_used_;
}

void PipelinedTakeMapper::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    work_.wait(lock, [&] { return stopping_ || finishing_ || !queue_.empty(); });
    if (stopping_) return;
    const bool last = queue_.empty();  // finishing, and every queued frame mapped
    std::optional<tracking::TrackedFrame> frame;
    if (!last) {
      frame = std::move(queue_.front());
      queue_.pop_front();
      changed_.notify_all();  // room in the queue
    }
    // The fit runs unlocked: the caller queues the next frames meanwhile.
    lock.unlock();
    std::vector<FapFrame> out;
    std::exception_ptr error;
    try {
      out = frame ? take_.push(*frame) : take_.finish();
    } catch (...) {
      error = std::current_exception();
    }
    const long calibrated_from = take_.calibration_frames_used();
    const auto motion = take_.calibration_motion();
    lock.lock();
    // The calibration's frame count is published with the first frames mapped after it.
    calibration_frames_used_ = calibrated_from;
    calibration_motion_ = motion;
    ready_.insert(ready_.end(), std::make_move_iterator(out.begin()),
                  std::make_move_iterator(out.end()));
    if (error || last) {
      error_ = error;
      done_ = true;
      changed_.notify_all();
      return;
    }
    changed_.notify_all();
  }
}

}  // namespace rostro::mapping
