#pragma once
// The cereal input archive that reads checkpoint payloads. It reads the byte format of cereal's
// BinaryOutputArchive, but from a bounded buffer, and it refuses every length prefix that could not fit in the bytes
// left before anything is allocated: a vector of n elements of at least s bytes each needs n * s <= bytes left. So a
// forged or damaged length (1e9 in a 32 KB file) fails at once instead of allocating gigabytes first. A bool must be
// stored as 0 or 1 (any other byte is not a bool; reading it as one is undefined behaviour).
//
// Only the types checkpoints hold are supported: arithmetic values, std::string, std::vector of those or of Vec3 or of
// std::string, std::optional, and classes with a serialize member. Anything else does not compile (no size tag
// overload exists for this archive), so a new field of another type cannot slip past the bounds.
//
// The archive knows the format version of the file it reads (format_version()): a component whose layout changed
// between formats asks it, and reads a retired slot of an older file with skip_retired_real (FluidSummary's last_dt,
// stored up to format 4).
#include <cereal/cereal.hpp>
#include <cereal/types/optional.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

class BoundedInputArchive : public cereal::InputArchive<BoundedInputArchive, cereal::AllowEmptyClassElision> {
 public:
  BoundedInputArchive(const char* data, std::size_t size, std::uint32_t format_version)
      : cereal::InputArchive<BoundedInputArchive, cereal::AllowEmptyClassElision>(this),
        data_(data),
        left_(size),
        format_version_(format_version) {}

  std::size_t bytes_left() const { return left_; }
  /// The checkpoint format of the bytes read (the file header's version).
  std::uint32_t format_version() const { return format_version_; }

  /// Reads a double an older format stored and the current one no longer holds, and lets it go. It must still be a
  /// finite number: a file whose bytes there are not one is malformed and refused like any other.
  void skip_retired_real(const char* what) {
    double value = 0.0;
    load_bytes(&value, sizeof value);
    if (!std::isfinite(value))
      throw cereal::Exception(std::string(what) + " (format " + std::to_string(format_version_) + ") = " +
                              std::to_string(value) + ": must be finite");
  }

  void load_bytes(void* out, std::size_t count) {
    if (count > left_)
      throw cereal::Exception("needs " + std::to_string(count) + " more bytes, " + std::to_string(left_) + " left");
    if (count > 0) std::memcpy(out, data_, count);
    data_ += count;
    left_ -= count;
  }

  /// Reads a length prefix (cereal's 64-bit size tag) of elements that take at least `element_bytes` each.
  std::size_t load_length(std::size_t element_bytes, const char* what) {
    std::uint64_t length = 0;
    load_bytes(&length, sizeof length);
    if (element_bytes > 0 && length > left_ / element_bytes)
      throw cereal::Exception(std::string("a ") + what + " of " + std::to_string(length) +
                              (element_bytes == 1 ? " bytes"
                                                  : " elements of at least " + std::to_string(element_bytes) + " bytes") +
                              " cannot fit in the " + std::to_string(left_) + " bytes left");
    return static_cast<std::size_t>(length);
  }

 private:
  const char* data_;
  std::size_t left_;
  std::uint32_t format_version_;
};

/// The fewest bytes one encoded element of type T takes (a string: its own length prefix).
template <class T>
constexpr std::size_t min_encoded_bytes() {
  if constexpr (std::is_arithmetic_v<T>) return sizeof(T);
  else if constexpr (std::is_same_v<T, Vec3>) return 3 * sizeof(double);
  else if constexpr (std::is_same_v<T, std::string>) return sizeof(std::uint64_t);
  else static_assert(sizeof(T) == 0, "add the smallest encoded size of this element type");
}

template <class T>
std::enable_if_t<std::is_arithmetic_v<T> && !std::is_same_v<T, bool>> CEREAL_LOAD_FUNCTION_NAME(
    BoundedInputArchive& archive, T& value) {
  archive.load_bytes(&value, sizeof value);
}

inline void CEREAL_LOAD_FUNCTION_NAME(BoundedInputArchive& archive, bool& value) {
  unsigned char byte = 0;
  archive.load_bytes(&byte, 1);
  if (byte > 1) throw cereal::Exception("a bool stored as " + std::to_string(byte));
  value = byte == 1;
}

/// cereal's std::optional names its parts; a binary archive stores only the values.
template <class T>
void CEREAL_LOAD_FUNCTION_NAME(BoundedInputArchive& archive, cereal::NameValuePair<T>& pair) {
  archive(pair.value);
}

inline void CEREAL_LOAD_FUNCTION_NAME(BoundedInputArchive& archive, std::string& text) {
  text.resize(archive.load_length(1, "string"));
  archive.load_bytes(text.data(), text.size());
}

template <class T, class Allocator>
void CEREAL_LOAD_FUNCTION_NAME(BoundedInputArchive& archive, std::vector<T, Allocator>& values) {
  static_assert(!std::is_same_v<T, bool>, "std::vector<bool> is not a checkpoint field type");
  values.resize(archive.load_length(min_encoded_bytes<T>(), "vector"));
  if constexpr (std::is_arithmetic_v<T>)
    archive.load_bytes(values.data(), values.size() * sizeof(T));
  else
    for (T& value : values) archive(value);
}

}  // namespace riffle
