#include "facecore/atomic_file.hpp"

#include <unistd.h>

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

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path destination)
    : destination_(std::move(destination)), temporary_(temporary_beside(destination_)) {
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (file_ == nullptr)
    throw InputError(destination_.string() + ": cannot write: " + std::strerror(errno));
  // Large writes are the common case (FAP streams, tracks): a big buffer saves syscalls.
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFile::write(std::string_view bytes) {
  if (bytes.empty()) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) failed_ = true;
}

void AtomicFile::commit() {
  if (file_ == nullptr) throw InputError(destination_.string() + ": already committed");
  const bool flushed = std::fflush(file_) == 0 && std::ferror(file_) == 0 && !failed_;
  const int saved_errno = errno;
  std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  if (!flushed) {
    std::filesystem::remove(temporary_, ec);
    throw InputError(destination_.string() + ": write failed: " + std::strerror(saved_errno));
  }
  std::filesystem::rename(temporary_, destination_, ec);
  if (ec) {
    std::filesystem::remove(temporary_, ec);
    throw InputError(destination_.string() +
                     ": cannot move the finished file into place: " + ec.message());
  }
}

}  // namespace rostro
