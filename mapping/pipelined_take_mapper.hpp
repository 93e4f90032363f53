#pragma once
// TakeMapper on a thread of its own, so that on a second core the FAP fit of frame N runs
// while the caller tracks frame N+1 (`rostro capture`). Same contract as TakeMapper: the FAP
// frames come back in the order their tracked frames were pushed, every frame once; without a
// profile the first frames are held back until the actor is calibrated on them; finish() maps
// what is left. The difference: push() does not wait for the frame's own fit, it returns
// whatever frames are ready so far (often none, or the previous one), and finish() waits for
// the rest. The FAPs are bit-identical to TakeMapper's: one worker maps the frames in order
// with the same TakeMapper.
//
// An error on the worker (InputError when the calibration fails) is thrown again on the
// caller's thread, by the push() or finish() after it. Errors come from the calibration, before
// any frame is mapped, so no mapped frame is lost with them. Destroying the mapper without
// finish() (an exception in the caller) stops the worker after its current frame and drops
// the frames not yet mapped; it never waits on the caller.

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "calib/actor_profile.hpp"
#include "calib/camera_intrinsics.hpp"
#include "facecore/fap_frame.hpp"
#include "mapping/fap_mapper.hpp"
#include "mapping/take_mapper.hpp"
#include "tracking/layout.hpp"
#include "tracking/tracked_frame.hpp"

namespace rostro::mapping {

class PipelinedTakeMapper {
 public:
  // As TakeMapper's. `max_queued`: tracked frames waiting for the worker before push() waits
  // for room (a fit slower than tracking must not let the queue grow through a long take).
  PipelinedTakeMapper(const tracking::MarkerLayout& layout, MapperOptions options,
                      const calib::CameraIntrinsics& camera,
                      std::optional<calib::ActorProfile> profile, long calibration_frames,
                      long max_queued = 16);
  ~PipelinedTakeMapper();
  PipelinedTakeMapper(const PipelinedTakeMapper&) = delete;
  PipelinedTakeMapper& operator=(const PipelinedTakeMapper&) = delete;

  // Queues `frame` for the worker and returns the FAP frames ready since the last call, in
  // order. Throws the worker's error (InputError from the calibration) once it has one.
  std::vector<FapFrame> push(tracking::TrackedFrame frame);
  // The end of the take: waits for every queued frame, calibrates on the frames held back if
  // that has not happened yet (InputError for a take with no frame at all), and returns the
  // rest. Nothing may be pushed after it.
  std::vector<FapFrame> finish();

  // Frames pushed and not yet returned: queued, being mapped, held back for the calibration,
  // or mapped and waiting to be returned.
  long held_back() const;
  // As TakeMapper's, set by the worker when it calibrates (before the first frames mapped
  // after it are returned).
  bool self_calibrated() const;
  long calibration_frames_used() const;
  std::optional<calib::NeutralMotion> calibration_motion() const;

 private:
  void run();  // the worker

  TakeMapper take_;  // touched only by the worker once it runs
  const std::size_t max_queued_;
  mutable std::mutex mutex_;
  std::condition_variable work_;     // to the worker: a frame, finish() or stop
  std::condition_variable changed_;  // to the caller: room in the queue, frames ready, done
  std::deque<tracking::TrackedFrame> queue_;
  std::vector<FapFrame> ready_;
  std::exception_ptr error_;
  bool finishing_ = false, stopping_ = false, done_ = false;
  long pushed_ = 0, returned_ = 0;
  long calibration_frames_used_ = 0;
  std::optional<calib::NeutralMotion> calibration_motion_;
  std::thread worker_;  // last: starts once everything above exists
};

}  // namespace rostro::mapping
