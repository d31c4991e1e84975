#pragma once
// One run at a time per output folder. A run or resume holds an exclusive flock(2) on OUT/.riffle.lock from before
// it writes anything until it exits; a second run into the same folder is refused at once instead of colliding on
// checkpoints and interleaving the rows of diagnostics.csv. The kernel drops the lock when the process dies, however
// it dies, so a crashed or killed run leaves no stale lock behind.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace riffle {

class OutputLockError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputLock {
 public:
  /// The lock file inside `directory` (which must exist).
  static std::filesystem::path lock_path(const std::filesystem::path& directory);

  /// Takes the lock without waiting. Throws OutputLockError naming the folder (and the holder's pid when known)
  /// if another process holds it, or if the lock file cannot be created.
  explicit OutputLock(const std::filesystem::path& directory);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace riffle
