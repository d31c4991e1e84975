#include "engine/output/checkpoint.hpp"

#include <cereal/archives/binary.hpp>
#include <cereal/types/optional.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/vector.hpp>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/output/replace_file.hpp"
#include "engine/output/checkpoint_archive.hpp"

namespace riffle {

namespace {
constexpr char kMagic[8] = {'R', 'I', 'F', 'F', 'L', 'E', 'C', 'P'};
constexpr std::size_t kHeaderSize = 8 + 4 + 4 + 8 + 8;

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

template <class T>
T get(const std::string& in, std::size_t offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  return value;
}

/// Whether the archive's format has the mean-flow column (every archive written now does).
template <class Archive>
bool holds_mean_flow(Archive& archive) {
  if constexpr (requires { archive.format_version(); })
    return archive.format_version() >= kFirstCheckpointVersionWithMeanFlow;
  else
    return true;
}

template <class Archive>
void archive_checkpoint(Archive& archive, CheckpointData& data) {
  World& world = data.world;
  archive(data.scene_file, data.scene_text, world.time, world.step);
  // The persistent parts, in World::kParts order; the others (neighbour lists, summaries, the fluid sample) are
  // rebuilt from these.
  World::for_each_part(world, [&](auto& part) {
    using Stored = typename detail::unwrap_optional<std::decay_t<decltype(part)>>::type;
    if constexpr (std::is_same_v<Stored, MeanFlowColumn>)
      if (!holds_mean_flow(archive)) return;  // older files have none
    if constexpr (Stored::kPersistent) archive(part);
  });
  archive(data.output);
}
}  // namespace

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char byte : bytes) {
    hash ^= byte;
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string encode_checkpoint(const CheckpointData& data) {
  std::ostringstream payload_stream(std::ios::binary);
  {
    cereal::BinaryOutputArchive archive(payload_stream);
    archive_checkpoint(archive, const_cast<CheckpointData&>(data));  // cereal's save path does not modify
  }
  const std::string payload = payload_stream.str();
  std::string out(kMagic, sizeof kMagic);
  put<std::uint32_t>(out, kCheckpointVersion);
  put<std::uint32_t>(out, 0);
  put<std::uint64_t>(out, payload.size());
  put<std::uint64_t>(out, fnv1a64(payload));
  out += payload;
  return out;
}

CheckpointData decode_checkpoint(const std::string& bytes, const std::string& name) {
  if (bytes.size() < kHeaderSize || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw CheckpointError(name + ": not a riffle checkpoint (missing RIFFLECP header)");
  const auto version = get<std::uint32_t>(bytes, 8);
  if (version < kOldestCheckpointVersionRead || version > kCheckpointVersion)
    throw CheckpointError(name + ": checkpoint format version " + std::to_string(version) +
                          ", but this riffle reads version " + std::to_string(kCheckpointVersion) + " (and " +
                          std::to_string(kOldestCheckpointVersionRead) + ")");
  const auto payload_size = get<std::uint64_t>(bytes, 16);
  const auto checksum = get<std::uint64_t>(bytes, 24);
  const std::size_t found = bytes.size() - kHeaderSize;
  if (found != payload_size)
    throw CheckpointError(name + ": checkpoint is " + (found < payload_size ? "truncated" : "oversized") +
                          ": header says " + std::to_string(payload_size) + " payload bytes, file has " +
                          std::to_string(found));
  const char* payload = bytes.data() + kHeaderSize;
  if (fnv1a64(std::string_view(payload, found)) != checksum)
    throw CheckpointError(name + ": checkpoint is corrupted (checksum mismatch)");
  CheckpointData data;
  data.format = version;
  try {
    // Bounded: no length prefix may claim more than the bytes left (engine/output/checkpoint_archive.hpp).
    BoundedInputArchive archive(payload, found, version);
    archive_checkpoint(archive, data);
    if (archive.bytes_left() != 0)
      throw std::runtime_error(std::to_string(archive.bytes_left()) + " bytes left over after the last field");
    World::for_each_part(data.world, [&](const auto& part) {
      using Stored = typename detail::unwrap_optional<std::decay_t<decltype(part)>>::type;
      if constexpr (Stored::kPersistent && requires(const Stored& table) { table.next_id; })  // entity tables
        if (part) check_field_sizes(*part, std::string(Stored::kName).c_str());
    });
  } catch (const std::exception& error) {
    throw CheckpointError(name + ": checkpoint payload cannot be read: " + error.what());
  }
  return data;
}

void write_checkpoint(const std::string& path, const CheckpointData& data) {
  try {
    replace_file(path, encode_checkpoint(data), Durability::kSync);
  } catch (const std::runtime_error& error) {
    throw CheckpointError(error.what());
  }
}

CheckpointData read_checkpoint(const std::string& path) {
  // Regular files only, and their size known before reading: a FIFO would block forever and /dev/zero or a
  // character device would be read until memory runs out. O_NONBLOCK keeps the open itself from waiting for a
  // FIFO's writer; the type is checked on the opened descriptor, so it cannot change between check and read.
  const int descriptor = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (descriptor < 0) throw CheckpointError(path + ": cannot open the checkpoint: " + std::strerror(errno));
  struct Closer {
    int descriptor;
    ~Closer() { ::close(descriptor); }
  } closer{descriptor};
  struct stat status {};
  if (::fstat(descriptor, &status) != 0)
    throw CheckpointError(path + ": cannot open the checkpoint: " + std::strerror(errno));
  if (!S_ISREG(status.st_mode)) {
    const std::string what = S_ISDIR(status.st_mode)    ? "a directory"
                             : S_ISFIFO(status.st_mode) ? "a FIFO"
                             : S_ISCHR(status.st_mode)  ? "a character device"
                                                        : "a special file";
    throw CheckpointError(path + ": not a regular file (" + what + "): a checkpoint must be a regular file");
  }
  const auto size = static_cast<std::size_t>(status.st_size);
  std::string bytes(size, '\0');
  std::size_t done = 0;
  while (done < size) {
    const ssize_t count = ::read(descriptor, bytes.data() + done, size - done);
    if (count < 0 && errno == EINTR) continue;
    if (count < 0) throw CheckpointError(path + ": cannot read the checkpoint: " + std::strerror(errno));
    if (count == 0) break;  // shrank while being read: the size check in decode_checkpoint names it
    done += static_cast<std::size_t>(count);
  }
  bytes.resize(done);
  return decode_checkpoint(bytes, path);
}

}  // namespace riffle
