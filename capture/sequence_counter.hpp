#pragma once
// Counts frames a driver dropped from the gaps in its sequence numbers.

#include <cstdint>
#include <optional>

namespace rostro::capture {

class SequenceCounter {
 public:
  // Records the driver's sequence number of a delivered frame and returns the number of
  // frames lost just before it (0 when it follows the previous one). A number that goes
  // backwards (driver restart, 32-bit wrap) starts counting afresh and reports no loss.
  std::int64_t observe(std::int64_t driver_sequence);
  // Frames lost so far.
  std::int64_t dropped() const { return dropped_; }
  // The sequence relative to the first frame seen (0, 1, 2 ... with gaps where frames were
  // lost), monotonic even across a driver restart.
  std::int64_t relative() const { return relative_; }

 private:
  std::optional<std::int64_t> last_;
  std::int64_t dropped_ = 0;
  std::int64_t relative_ = -1;
};

}  // namespace rostro::capture
