#include "engine/output/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace riffle {

namespace fs = std::filesystem;

namespace {

/// The pid the holder wrote into the lock file, or "" (it may not have written it yet).
std::string holder_pid(int fd) {
  char text[32] = {};
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  if (got <= 0) return "";
  std::size_t digits = 0;
  while (digits < static_cast<std::size_t>(got) && text[digits] >= '0' && text[digits] <= '9') ++digits;
  return std::string(text, digits);
}

}  // namespace

fs::path OutputLock::lock_path(const fs::path& directory) { return directory / ".riffle.lock"; }

OutputLock::OutputLock(const fs::path& directory) {
  const fs::path path = lock_path(directory);
  // Never truncated on open: the holder's pid stays readable for the message of the process refused.
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw OutputLockError(path.string() + ": cannot create the output folder's lock file: " + std::strerror(errno));
  int result;
  do result = ::flock(fd_, LOCK_EX | LOCK_NB);
  while (result != 0 && errno == EINTR);
  if (result != 0) {
    const int error_number = errno;
    const std::string pid = error_number == EWOULDBLOCK ? holder_pid(fd_) : "";
    ::close(fd_);
    fd_ = -1;
    if (error_number != EWOULDBLOCK)
      throw OutputLockError(path.string() + ": cannot lock the output folder: " + std::strerror(error_number));
    throw OutputLockError(directory.string() + ": another riffle run" + (pid.empty() ? "" : " (pid " + pid + ")") +
                          " is writing into this output folder; wait for it to finish or choose another --out");
  }
  // Only the holder writes: the pid names it in the message of a run that is refused.
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) (void)!::pwrite(fd_, pid.data(), pid.size(), 0);
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the only descriptor releases the flock
}

}  // namespace riffle
