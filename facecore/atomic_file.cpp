#include "facecore/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "facecore/error.hpp"

namespace rostro {
namespace {

std::filesystem::path temporary_beside(const std::filesystem::path& destination) {
  // The process id keeps two rostro processes writing the same name apart.
  std::filesystem::path tmp = destination;
  tmp += ".tmp-" + std::to_string(::getpid());
  return tmp;
}

// The temporaries a fatal signal must not leave behind. Fixed storage, so that a signal
// handler can walk it: a slot is claimed (1), filled, then published (2).
constexpr int kSlots = 64;
constexpr std::size_t kPathMax = 4096;
struct Slot {
  std::atomic<int> state{0};
  char path[kPathMax];
};
Slot g_slots[kSlots];

int claim_slot(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (text.size() >= kPathMax) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;  // more open outputs than slots: that one is only removed by its destructor
}

void release_slot(int& slot) {
  if (slot >= 0) g_slots[slot].state.store(0);
  slot = -1;
}

}  // namespace

std::string describe_write_error(const std::filesystem::path& path, const std::string& doing,
                                 int error) {
  if (error == ENOSPC) return path.string() + ": no space left on device";
  if (error == EDQUOT) return path.string() + ": disk quota exceeded";
  return path.string() + ": " + doing + ": " + std::strerror(error != 0 ? error : EIO);
}

void AtomicFile::remove_temporaries_from_signal_handler() {
  for (Slot& slot : g_slots)
    if (slot.state.load() == 2) ::unlink(slot.path);
}

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(std::move(destination)), temporary_(temporary_beside(destination_)) {
  slot_ = claim_slot(temporary_);
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr) {
    const int error = errno;
    release_slot(slot_);
    throw InputError(describe_write_error(destination_, "cannot write", error));
  }
  // Large writes are the common case (FAP streams, tracks): a big buffer saves syscalls.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
  release_slot(slot_);
}

void AtomicFile::fail(const std::string& doing, int error) const {
  throw InputError(describe_write_error(destination_, doing, error));
}

void AtomicFile::write(std::string_view bytes) {
  if (bytes.empty() || error_ != 0) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    error_ = errno != 0 ? errno : EIO;
}

void AtomicFile::flush() {
  if (file_ == nullptr) throw InputError(destination_.string() + ": already committed");
  if (error_ == 0 && std::fflush(file_) != 0) error_ = errno != 0 ? errno : EIO;
  if (error_ != 0) fail("write failed", error_);
}

void AtomicFile::append_now(std::string_view bytes) {
  flush();
  const int fd = ::fileno(file_);
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error_ = n < 0 ? errno : ENOSPC;
      fail("write failed", error_);
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void AtomicFile::write_at(off_t offset, std::string_view bytes) {
  const ssize_t n = ::pwrite(::fileno(file_), bytes.data(), bytes.size(), offset);
  if (n != static_cast<ssize_t>(bytes.size())) fail("write failed", n < 0 ? errno : EIO);
}

void AtomicFile::truncate(off_t size) {
  // append_now() leaves nothing in the stdio buffer: cut the file and put the write
  // position at its new end.
  std::clearerr(file_);
  const int fd = ::fileno(file_);
  if (::ftruncate(fd, size) != 0 || ::lseek(fd, size, SEEK_SET) != size)
    fail("cannot cut back to the frames written", errno);
  error_ = 0;
}

void AtomicFile::sync() {
  flush();
  if (::fdatasync(::fileno(file_)) != 0) fail("cannot sync to disk", errno);
}

void AtomicFile::commit() {
  commit_as(destination_);
}

void AtomicFile::commit_as(const std::filesystem::path& destination) {
  if (file_ == nullptr) throw InputError(destination_.string() + ": already committed");
  if (error_ == 0 && (std::fflush(file_) != 0 || std::ferror(file_) != 0))
    error_ = errno != 0 ? errno : EIO;
  const int error = error_;
  std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  if (error != 0) {
    std::filesystem::remove(temporary_, ec);
    release_slot(slot_);
    fail("write failed", error);
  }
  std::filesystem::rename(temporary_, destination, ec);
  if (ec) {
    std::filesystem::remove(temporary_, ec);
    release_slot(slot_);
    throw InputError(destination.string() +
                     ": cannot move the finished file into place: " + ec.message());
  }
  release_slot(slot_);
}

}  // namespace rostro
