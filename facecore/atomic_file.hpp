#pragma once
// An output file written beside its destination under a temporary name and renamed into
// place on commit(): readers never see half a file, and an earlier file of the same name
// survives any failure before commit().
//
// Streaming writers that must survive a killed process (take files) also use flush(),
// write_at(), truncate() and sync() to keep the temporary readable at every moment; see
// fap_file.cpp. A full disk is reported as "PATH: no space left on device".

#include <sys/types.h>

#include <cstdio>
#include <filesystem>
#include <string>
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
  // Buffered; a failure is remembered and reported by flush() or commit().
  void write(std::string_view bytes);
  // Hands everything written so far to the kernel (it then survives a killed process).
  // Throws InputError naming the file and the cause ("no space left on device").
  void flush();
  // Writes straight to the kernel, past the stdio buffer (flushed first). Throws like flush().
  void append_now(std::string_view bytes);
  // Overwrites bytes already flushed, at `offset`, without moving the write position.
  void write_at(off_t offset, std::string_view bytes);
  // Cuts the temporary back to `size` bytes after a failed append_now() (writers that mix in
  // write() must not call it) and forgets the failure.
  void truncate(off_t size);
  // flush() and then the data to the disk itself (it then survives a power loss).
  void sync();
  // Flushes, closes and renames into place. Throws InputError on any I/O failure.
  void commit();
  // The same under another name (a take kept after a failure goes to NAME.partial.fap).
  void commit_as(const std::filesystem::path& destination);

  const std::filesystem::path& destination() const { return destination_; }
  const std::filesystem::path& temporary() const { return temporary_; }

  // Removes every temporary file not yet committed or removed, using only calls a signal
  // handler may make. For the handler of a signal that ends the program.
  static void remove_temporaries_from_signal_handler();

 private:
  [[noreturn]] void fail(const std::string& doing, int error) const;

  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::FILE* file_ = nullptr;
  int error_ = 0;  // errno of the first failed write, 0 when none
  int slot_ = -1;  // in the table of temporaries removed on a fatal signal
};

// "PATH: no space left on device" for ENOSPC, else "PATH: DOING: strerror".
std::string describe_write_error(const std::filesystem::path& path, const std::string& doing,
                                 int error);

}  // namespace rostro
