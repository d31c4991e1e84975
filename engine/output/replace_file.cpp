#include "engine/output/replace_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

namespace riffle {

namespace fs = std::filesystem;

namespace {

std::atomic<unsigned long long> g_temporary_counter{0};

std::runtime_error io_error(const fs::path& path, const std::string& what, int error_number) {
  return std::runtime_error(path.string() + ": " + what + ": " + std::strerror(error_number));
}

/// Writes all of `bytes`; a signal (SIGINT, SIGTERM) may interrupt a write part way.
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd, bytes.data(), bytes.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

/// Makes the rename itself durable: the new directory entry is on disk once the directory is synced.
void sync_directory(const fs::path& directory) {
  const int fd = ::open(directory.empty() ? "." : directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // some file systems refuse to open directories; the data itself was synced
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

fs::path unique_temporary_path(const fs::path& path) {
  const unsigned long long counter = g_temporary_counter.fetch_add(1);
  return path.string() + "." + std::to_string(::getpid()) + "." + std::to_string(counter) + ".tmp";
}

void replace_file(const fs::path& path, std::string_view bytes, Durability durability) {
  fs::path temporary;
  int fd = -1;
  // O_EXCL: a stale temporary file of a dead process that had the same pid is never written into or renamed.
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temporary = unique_temporary_path(path);
    fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0 && errno != EEXIST) throw io_error(temporary, "cannot create a temporary file", errno);
  }
  if (fd < 0) throw io_error(temporary, "cannot create a temporary file", EEXIST);
  const auto fail = [&](const std::string& what) {
    const int error_number = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    return io_error(temporary, what, error_number);
  };
  if (!write_all(fd, bytes)) throw fail("write failed (disk full?)");
  if (durability == Durability::kSync && ::fsync(fd) != 0) throw fail("cannot flush to disk");
  if (::close(fd) != 0) {
    const int error_number = errno;
    ::unlink(temporary.c_str());
    throw io_error(temporary, "write failed (disk full?)", error_number);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error_number = errno;
    ::unlink(temporary.c_str());
    throw io_error(path, "cannot rename the temporary file " + temporary.filename().string() + " into place",
                   error_number);
  }
  if (durability == Durability::kSync) sync_directory(path.parent_path());
}

bool is_temporary_name(const std::string& file_name) {
  constexpr std::string_view kSuffix = ".tmp";
  if (file_name.size() <= kSuffix.size() ||
      file_name.compare(file_name.size() - kSuffix.size(), kSuffix.size(), kSuffix) != 0)
    return false;
  // Walk back over ".<counter>" and ".<pid>": two dot-led runs of digits before ".tmp", after a non-empty name.
  std::size_t end = file_name.size() - kSuffix.size();
  for (int field = 0; field < 2; ++field) {
    std::size_t begin = end;
    while (begin > 0 && file_name[begin - 1] >= '0' && file_name[begin - 1] <= '9') --begin;
    if (begin == end || begin == 0 || file_name[begin - 1] != '.') return false;
    end = begin - 1;
  }
  return end > 0;
}

std::size_t remove_stale_temporaries(const fs::path& directory) {
  std::size_t removed = 0;
  std::error_code error;
  for (fs::directory_iterator entry(directory, error), last; !error && entry != last; entry.increment(error)) {
    std::error_code ignored;
    if (entry->is_regular_file(ignored) && is_temporary_name(entry->path().filename().string()) &&
        fs::remove(entry->path(), ignored))
      ++removed;
  }
  return removed;
}

}  // namespace riffle
