#pragma once
// Hands items from one pipeline stage to the next so that the newest always wins: a put()
// replaces an item the consumer has not taken yet (counted as skipped), so a slow stage
// never builds a queue and latency never grows.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

namespace rostro::live {

template <typename T>
class LatestSlot {
 public:
  void put(T item) {
    {
      std::lock_guard lock(mutex_);
      if (item_) ++skipped_;
      item_ = std::move(item);
    }
    ready_.notify_one();
  }

  // Waits for an item; nullopt once close() was called and the slot is empty.
  std::optional<T> take() {
    std::unique_lock lock(mutex_);
    ready_.wait(lock, [&] { return item_.has_value() || closed_; });
    std::optional<T> out = std::move(item_);
    item_.reset();
    return out;
  }

  // Like take(), but gives up after `timeout` (nullopt), so a consumer with other duties
  // (a window's events) keeps going while nothing arrives. closed() tells the two apart.
  template <typename Rep, typename Period>
  std::optional<T> take_for(std::chrono::duration<Rep, Period> timeout) {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [&] { return item_.has_value() || closed_; });
    std::optional<T> out = std::move(item_);
    item_.reset();
    return out;
  }

  // True once close() was called and nothing is left to take.
  bool closed() const {
    std::lock_guard lock(mutex_);
    return closed_ && !item_;
  }

  // No more items: wakes the consumer, which drains what is left and then gets nullopt.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  std::int64_t skipped() const {
    std::lock_guard lock(mutex_);
    return skipped_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::optional<T> item_;
  bool closed_ = false;
  std::int64_t skipped_ = 0;
};

}  // namespace rostro::live
