#include "capture/sequence_counter.hpp"

namespace rostro::capture {

std::int64_t SequenceCounter::observe(std::int64_t driver_sequence) {
  std::int64_t lost = 0;
  if (!last_ || driver_sequence <= *last_) {
    relative_ += 1;
  } else {
    lost = driver_sequence - *last_ - 1;
    relative_ += driver_sequence - *last_;
  }
  last_ = driver_sequence;
  dropped_ += lost;
  return lost;
}

}  // namespace rostro::capture
