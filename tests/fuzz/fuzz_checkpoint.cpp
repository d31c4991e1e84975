// libFuzzer harness for the checkpoint loader (docs/RELIABILITY.md): the same code `riffle resume` runs, from the
// bytes on: decode (bounded lengths), validate against the embedded scene, build the Simulation, and step what is
// accepted twice. A refusal must be a CheckpointError or a SceneError; anything else, a crash, a hang or a large
// allocation is a finding.
//
// The checksum has no key, so the interesting inputs are those whose checksum is valid: the custom mutator below
// mutates the payload and then rewrites the header's size and checksum. It leaves the scene (the payload's first two
// strings) to LLVMFuzzerMutate's reach only through word overwrites: the scene reader has its own fuzzer, and a
// mutated scene mostly fails to parse, which would waste this one's time.
//
// Seeds: tests/fuzz/corpus/checkpoint (small checkpoints; tests/fuzz/make_checkpoint_corpus.sh writes them).
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "engine/output/checkpoint.hpp"
#include "engine/toml/scene_reader.hpp"
#include "engine/run/simulation.hpp"

using namespace riffle;

namespace {

constexpr std::size_t kHeaderSize = 32;  // magic, version, zero, payload size, checksum (engine/output/checkpoint.hpp)
constexpr char kMagic[8] = {'R', 'I', 'F', 'F', 'L', 'E', 'C', 'P'};

bool has_header(const std::uint8_t* data, std::size_t size) {
  return size >= kHeaderSize && std::memcmp(data, kMagic, sizeof kMagic) == 0;
}

std::uint64_t read_u64(const std::uint8_t* at) {
  std::uint64_t value;
  std::memcpy(&value, at, sizeof value);
  return value;
}

/// Makes the header describe the payload that follows it: its size and checksum.
void seal(std::uint8_t* data, std::size_t size) {
  const std::uint64_t payload_size = size - kHeaderSize;
  const std::uint64_t checksum =
      fnv1a64(std::string_view(reinterpret_cast<const char*>(data) + kHeaderSize, payload_size));
  std::memcpy(data + 16, &payload_size, sizeof payload_size);
  std::memcpy(data + 24, &checksum, sizeof checksum);
}

/// Where the payload's two leading strings (scene file name and scene text) end, or the payload start if their
/// lengths do not fit.
std::size_t scene_end(const std::uint8_t* data, std::size_t size) {
  std::size_t at = kHeaderSize;
  for (int field = 0; field < 2; ++field) {
    if (size - at < 8) return kHeaderSize;
    const std::uint64_t length = read_u64(data + at);
    at += 8;
    if (length > size - at) return kHeaderSize;
    at += static_cast<std::size_t>(length);
  }
  return at;
}

/// Values that break code which trusts its input: non-finite, zero, negative, subnormal, huge, and integer limits.
void overwrite_word(std::uint8_t* data, std::size_t size, std::minstd_rand& random) {
  static const double kDoubles[] = {std::numeric_limits<double>::quiet_NaN(),
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(),
                                    0.0, -0.0, -1.0, 1.0, 5e-324, 1e-300, 1e9, -1e9, 1e300, 2.5e-3};
  static const std::uint64_t kIntegers64[] = {0, 1, 2, 3, 7, 99, 1000000000ull, 0x7fffffffull, 0xffffffffull,
                                              0x100000000ull, 0x7fffffffffffffffull, 0xffffffffffffffffull};
  static const std::uint32_t kIntegers32[] = {0, 1, 2, 3, 6, 7, 99, 1000000000u, 0x7fffffffu, 0x80000000u, 0xffffffffu};
  if (size < kHeaderSize + 8) return;
  const std::size_t payload = size - kHeaderSize;
  const int kind = static_cast<int>(random() % 3);
  const std::size_t width = kind == 2 ? 4 : 8;
  // Fields are packed without padding, so half the writes go to any offset and half to aligned ones.
  std::size_t offset = random() % (payload - width + 1);
  if (random() % 2) offset -= offset % width;
  std::uint8_t* at = data + kHeaderSize + offset;
  if (kind == 0) {
    const double value = kDoubles[random() % std::size(kDoubles)];
    std::memcpy(at, &value, sizeof value);
  } else if (kind == 1) {
    const std::uint64_t value = kIntegers64[random() % std::size(kIntegers64)];
    std::memcpy(at, &value, sizeof value);
  } else {
    const std::uint32_t value = kIntegers32[random() % std::size(kIntegers32)];
    std::memcpy(at, &value, sizeof value);
  }
}

}  // namespace

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  std::minstd_rand random(seed);
  if (!has_header(data, size) || max_size < kHeaderSize + 16) return LLVMFuzzerMutate(data, size, max_size);
  const std::size_t keep = scene_end(data, size);
  const int rounds = 1 + static_cast<int>(random() % 3);
  for (int round = 0; round < rounds; ++round) {
    if (random() % 2 == 0 && max_size > keep) {
      size = keep + LLVMFuzzerMutate(data + keep, size - keep, max_size - keep);
    } else {
      overwrite_word(data, size, random);
    }
  }
  seal(data, size);
  return size;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // One thread: the fuzzer measures coverage and time per input, and the engine's results do not depend on it.
  static tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  std::unique_ptr<Simulation> simulation;
  try {
    simulation = Simulation::from_checkpoint_data(decode_checkpoint(bytes, "fuzz.ckpt"), "fuzz.ckpt");
  } catch (const CheckpointError&) {
    return 0;
  } catch (const SceneError&) {
    return 0;
  }
  // Accepted: the engine must take it from here. Two steps of a small scene; a diagnosis (a grain leaving the
  // domain, a collapsing fluid step) is an answer too.
  for (int step = 0; step < 2 && simulation->world().step_status.ok(); ++step) simulation->step();
  return 0;
}
