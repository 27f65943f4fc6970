#pragma once
// One run per output directory: a run holds an flock(2) on DIR/.tsuchi.lock for as long as it
// writes there, so a second run into the same directory stops at once instead of mixing its
// frames with the first one's. The kernel drops the lock when the holder ends in any way (even
// SIGKILL), so the lock file a killed run leaves behind is recognised as stale and taken over.
#include <string>

namespace tsuchi {

class DirectoryLock {
 public:
  // Takes the lock of an existing directory, or throws OutputError naming the process id of the
  // run that holds it.
  explicit DirectoryLock(const std::string& dir);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

  static constexpr const char* file_name = ".tsuchi.lock";

  // Throws the OutputError of the constructor when another run holds the directory's lock, without
  // creating or changing anything: a second run can stop before it builds a large model.
  static void refuse_if_held(const std::string& dir);

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace tsuchi
