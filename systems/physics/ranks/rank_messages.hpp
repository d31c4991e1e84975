#pragma once
// What the decompositions over MPI ranks put in their messages (systems/physics/ranks/grain_ranks.hpp,
// fluid_ranks.hpp): plain values as bytes and back, an entity's every field (a table's for_each_field order), and
// a whole table gathered at rank 0 in id order for the outputs.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "components/soa.hpp"
#include "components/vec.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

/// Plain values into bytes; a Vec3 as its three doubles.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<std::byte>& out) : out_(out) {}
  template <class T>
  void put(const T& value) {
    if constexpr (std::is_same_v<T, Vec3>) {
      const double xyz[3] = {value.x(), value.y(), value.z()};
      append(xyz, sizeof xyz);
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      append(&value, sizeof value);
    }
  }

 private:
  void append(const void* data, std::size_t bytes) {
    const std::size_t at = out_.size();
    out_.resize(at + bytes);
    std::memcpy(out_.data() + at, data, bytes);
  }
  std::vector<std::byte>& out_;
};

/// Bytes back into plain values, in the order written; a message that ends early is a logic error.
class ByteReader {
 public:
  explicit ByteReader(const std::vector<std::byte>& in) : in_(in) {}
  template <class T>
  T get() {
    if constexpr (std::is_same_v<T, Vec3>) {
      double xyz[3];
      take(xyz, sizeof xyz);
      return Vec3(xyz[0], xyz[1], xyz[2]);
    } else {
      T value;
      take(&value, sizeof value);
      return value;
    }
  }
  bool done() const { return at_ == in_.size(); }

 private:
  void take(void* data, std::size_t bytes) {
    if (at_ + bytes > in_.size()) throw std::logic_error("rank message: it ended early");
    std::memcpy(data, in_.data() + at_, bytes);
    at_ += bytes;
  }
  const std::vector<std::byte>& in_;
  std::size_t at_ = 0;
};

/// Reads the ghosts each rank sent, in rank order, one record at a time (`read_one(in)` appends one ghost's fields)
/// and returns where each rank's ghosts start ([ranks + 1] offsets).
template <class ReadOne>
std::vector<std::uint32_t> read_ghost_records(const std::vector<std::vector<std::byte>>& incoming, ReadOne&& read_one) {
  std::vector<std::uint32_t> offsets(incoming.size() + 1, 0);
  std::uint32_t read = 0;
  for (std::size_t r = 0; r < incoming.size(); ++r) {
    offsets[r] = read;
    ByteReader in(incoming[r]);
    for (; !in.done(); ++read) read_one(in);
  }
  offsets[incoming.size()] = read;
  return offsets;
}

/// Every field of entity `slot` of an entity table, in the table's order.
template <class Table>
void pack_entity(const Table& table, std::size_t slot, ByteWriter& out) {
  Table::for_each_field(table, [&](const FieldInfo&, const auto& field) { out.put(field[slot]); });
}

/// Fills entity `slot` (the table already resized) from a pack_entity message.
template <class Table>
void unpack_entity(Table& table, std::size_t slot, ByteReader& in) {
  Table::for_each_field(table, [&](const FieldInfo&, auto& field) {
    using Value = typename std::decay_t<decltype(field)>::value_type;
    field[slot] = in.template get<Value>();
  });
}

/// The bytes pack_entity writes for one entity of the table.
template <class Table>
std::size_t packed_entity_bytes() {
  std::vector<std::byte> probe;
  ByteWriter one(probe);
  Table sample;
  resize_fields(sample, 1);
  pack_entity(sample, 0, one);
  return probe.size();
}

/// Every rank's entities at rank 0, ordered by id (a whole world's table for the outputs); an empty table elsewhere,
/// with every rank's next_id (all built the same world, and no entity is added after). Collective.
template <class Table>
Table gather_entities_at_root(const Table& table) {
  std::vector<std::byte> mine;
  ByteWriter out(mine);
  for (std::size_t i = 0; i < table.size(); ++i) pack_entity(table, i, out);
  const std::vector<std::vector<std::byte>> all = ranks::gather_at_root(mine);
  Table gathered;
  gathered.next_id = table.next_id;
  if (ranks::rank() != 0) return gathered;
  const std::size_t bytes_per_entity = packed_entity_bytes<Table>();
  std::size_t total = 0;
  for (const auto& bytes : all) {
    if (bytes.size() % bytes_per_entity != 0) throw std::logic_error("gather_entities_at_root: a message of part entities");
    total += bytes.size() / bytes_per_entity;
  }
  resize_fields(gathered, total);
  std::size_t slot = 0;
  for (const auto& bytes : all) {
    ByteReader in(bytes);
    while (!in.done()) unpack_entity(gathered, slot++, in);
  }
  std::vector<std::size_t> order(total);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return gathered.id[a] < gathered.id[b]; });
  permute_fields(gathered, order);
  return gathered;
}

}  // namespace riffle
