#pragma once
// A FapSource over a stream already in memory (a generated clip, a test), so it can go
// through the same render_stream() path as a file.

#include <utility>

#include "facecore/fap_io.hpp"

namespace rostro::render {

class FapStreamSource : public FapSource {
 public:
  explicit FapStreamSource(FapStream stream) : stream_(std::move(stream)) {
    stream_.header.frame_count = static_cast<long>(stream_.frames.size());
  }
  const FapHeader& header() const override { return stream_.header; }
  bool next(FapFrame& frame) override {
    if (next_ >= stream_.frames.size()) return false;
    frame = stream_.frames[next_++];
    return true;
  }

 private:
  FapStream stream_;
  std::size_t next_ = 0;
};

}  // namespace rostro::render
