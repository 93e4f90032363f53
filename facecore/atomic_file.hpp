#pragma once
// An output file written beside its destination under a temporary name and renamed into
// place on commit(): readers never see half a file, and an earlier file of the same name
// survives any failure before commit().

#include <cstdio>
#include <filesystem>
#include <string_view>

namespace rostro {

class AtomicFile {
 public:
  // Throws InputError when the temporary file cannot be created.
  explicit AtomicFile(std::filesystem::path destination);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::FILE* handle() { return file_; }
  void write(std::string_view bytes);
  // Flushes, closes and renames into place. Throws InputError on any I/O failure.
  void commit();

  const std::filesystem::path& destination() const { return destination_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;
};

}  // namespace rostro
