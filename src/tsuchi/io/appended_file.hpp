#pragma once
// A text file that grows by whole rows (global.csv, recorders.csv): rows are appended as they
// come, so memory and checkpoints stay small however long the run. The file's length and the
// CRC-32 of its bytes are kept, so a checkpoint can record exactly which rows it covers and a
// restart can cut the file back to them (rows written after the checkpoint are written again).
#include <cstdint>
#include <string>
#include <string_view>

namespace tsuchi {

class AppendedFile {
 public:
  AppendedFile() = default;
  ~AppendedFile();
  AppendedFile(const AppendedFile&) = delete;
  AppendedFile& operator=(const AppendedFile&) = delete;

  // Starts the file afresh with `header`; throws OutputError.
  void create(const std::string& path, std::string_view header);
  // Continues a file of which the first `bytes` bytes must have CRC-32 `crc`; cuts off what follows.
  // Throws InputError (naming the file and what to do) when the file is missing, shorter or
  // different: the checkpoint belongs to a run that wrote elsewhere, or the file was rewritten since.
  void resume(const std::string& path, std::uint64_t bytes, std::uint32_t crc);

  // Queues a row; written out by flush(), or when 64 KiB are queued. Rows are written whole: a
  // failed write is cut back to the last complete row.
  void append(std::string_view row);
  // Writes the queued rows; with `sync`, also to disk (before a checkpoint names their length).
  void flush(bool sync);

  bool is_open() const { return fd_ >= 0; }
  std::uint64_t bytes() const { return bytes_; }  // including queued rows
  std::uint32_t crc() const { return crc_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::string queued_;
  std::uint64_t bytes_ = 0, written_ = 0;
  std::uint32_t crc_ = 0;
};

// zlib's CRC-32 of `bytes` continued from `crc` (0 to start).
std::uint32_t crc32_update(std::uint32_t crc, std::string_view bytes);

}  // namespace tsuchi
