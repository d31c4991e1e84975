#include "systems/physics/ranks/rank_comm.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#ifdef RIFFLE_WITH_MPI
#include <mpi.h>
#endif

namespace riffle::ranks {

namespace {
CallTimes times;

/// Adds the wall time of its life to one of `times`' totals.
class CallTimer {
 public:
  CallTimer(double& seconds, std::uint64_t& calls)
      : seconds_(seconds), start_(std::chrono::steady_clock::now()) {
    ++calls;
  }
  ~CallTimer() { seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
};
}  // namespace

const CallTimes& call_times() { return times; }

#ifdef RIFFLE_WITH_MPI

namespace {
bool started_here = false;

void finalise() {
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised && started_here) MPI_Finalize();
}

bool running() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised && !finalised;
}

void check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string(call) + " failed (MPI error " + std::to_string(code) + ")");
}

/// The rank layer's own communicator: MPI_COMM_WORLD duplicated at the first exchange or reduction (every rank makes
/// the same calls in the same order, so the first is collective). hypre's solves run on MPI_COMM_WORLD and may post
/// receives from any source: on a communicator of their own, the point-to-point exchanges here can never be taken
/// by one of them, whatever their tags.
MPI_Comm comm() {
  static MPI_Comm duplicate = MPI_COMM_NULL;
  if (duplicate == MPI_COMM_NULL) check(MPI_Comm_dup(MPI_COMM_WORLD, &duplicate), "MPI_Comm_dup");
  return duplicate;
}

int to_int(std::size_t count) {
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("an MPI message of " + std::to_string(count) + " bytes is beyond MPI's int counts");
  return static_cast<int>(count);
}
}  // namespace

bool mpi_built() { return true; }

void start_mpi() {
  static std::once_flag once;
  std::call_once(once, [] {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised) return;
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
      throw std::runtime_error("could not initialise MPI");
    if (provided < MPI_THREAD_SERIALIZED)
      throw std::runtime_error("riffle needs MPI_THREAD_SERIALIZED (this MPI gives " + std::to_string(provided) + ")");
    started_here = true;
    std::atexit(finalise);
  });
}

int rank() {
  if (!running()) return 0;
  int value = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &value);
  return value;
}

int size() {
  if (!running()) return 1;
  int value = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &value);
  return value;
}

bool any(bool flag) {
  if (size() == 1) return flag;
  const CallTimer timer(times.reduce_seconds, times.reductions);
  int local = flag ? 1 : 0, global = 0;
  check(MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_LOR, comm()), "MPI_Allreduce");
  return global != 0;
}

double max(double value) {
  if (size() == 1) return value;
  const CallTimer timer(times.reduce_seconds, times.reductions);
  double global = 0.0;
  check(MPI_Allreduce(&value, &global, 1, MPI_DOUBLE, MPI_MAX, comm()), "MPI_Allreduce");
  return global;
}

std::vector<double> gather_all(const std::vector<double>& values, std::vector<std::size_t> counts) {
  if (size() == 1) return values;
  std::vector<int> sizes(static_cast<std::size_t>(size()));
  if (counts.empty()) {  // the lengths not known beforehand: gathered first
    const CallTimer timer(times.reduce_seconds, times.reductions);
    const int count = to_int(values.size());
    check(MPI_Allgather(&count, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm()), "MPI_Allgather");
    counts.assign(sizes.begin(), sizes.end());
  }
  if (counts.size() != sizes.size() || counts[static_cast<std::size_t>(rank())] != values.size())
    throw std::logic_error("ranks::gather_all: the counts must be every rank's, this rank's its values' length");
  const CallTimer timer(times.reduce_seconds, times.reductions);
  std::vector<int> displacements(counts.size(), 0);
  for (std::size_t r = 0; r < counts.size(); ++r) sizes[r] = to_int(counts[r]);
  for (std::size_t r = 1; r < counts.size(); ++r) displacements[r] = displacements[r - 1] + sizes[r - 1];
  std::vector<double> all(static_cast<std::size_t>(displacements.back() + sizes.back()));
  check(MPI_Allgatherv(values.data(), sizes[static_cast<std::size_t>(rank())], MPI_DOUBLE, all.data(), sizes.data(),
                       displacements.data(), MPI_DOUBLE, comm()),
        "MPI_Allgatherv");
  return all;
}

std::vector<double> sum_in_rank_order(const std::vector<double>& values) {
  if (size() == 1) return values;
  // The same length on every rank: one MPI_Allgather, no exchange of counts first.
  std::vector<double> all(values.size() * static_cast<std::size_t>(size()));
  {
    const CallTimer timer(times.reduce_seconds, times.reductions);
    check(MPI_Allgather(values.data(), to_int(values.size()), MPI_DOUBLE, all.data(), to_int(values.size()), MPI_DOUBLE,
                        comm()),
          "MPI_Allgather");
  }
  std::vector<double> sum(values.size(), 0.0);
  for (std::size_t r = 0; r < static_cast<std::size_t>(size()); ++r)
    for (std::size_t k = 0; k < values.size(); ++k) sum[k] += all[r * values.size() + k];
  return sum;
}

std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& outgoing) {
  const auto ranks = static_cast<std::size_t>(size());
  if (outgoing.size() != ranks)
    throw std::logic_error("ranks::exchange: " + std::to_string(outgoing.size()) + " buffers for " +
                           std::to_string(ranks) + " ranks");
  if (ranks == 1) return outgoing;
  const CallTimer timer(times.exchange_seconds, times.exchanges);
  std::vector<int> send_counts(ranks), receive_counts(ranks), send_at(ranks, 0), receive_at(ranks, 0);
  for (std::size_t r = 0; r < ranks; ++r) send_counts[r] = to_int(outgoing[r].size());
  check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm()),
        "MPI_Alltoall");
  std::vector<std::byte> send_buffer, receive_buffer;
  for (std::size_t r = 0; r < ranks; ++r) {
    send_at[r] = to_int(send_buffer.size());
    send_buffer.insert(send_buffer.end(), outgoing[r].begin(), outgoing[r].end());
  }
  std::size_t total = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    receive_at[r] = to_int(total);
    total += static_cast<std::size_t>(receive_counts[r]);
  }
  receive_buffer.resize(total);
  check(MPI_Alltoallv(send_buffer.data(), send_counts.data(), send_at.data(), MPI_BYTE, receive_buffer.data(),
                      receive_counts.data(), receive_at.data(), MPI_BYTE, comm()),
        "MPI_Alltoallv");
  std::vector<std::vector<std::byte>> incoming(ranks);
  for (std::size_t r = 0; r < ranks; ++r)
    incoming[r].assign(receive_buffer.begin() + receive_at[r],
                       receive_buffer.begin() + receive_at[r] + receive_counts[r]);
  return incoming;
}

std::vector<std::vector<std::byte>> exchange_known(const std::vector<std::vector<std::byte>>& outgoing,
                                                   const std::vector<std::size_t>& incoming_bytes) {
  const auto ranks = static_cast<std::size_t>(size());
  const auto me = static_cast<std::size_t>(rank());
  if (outgoing.size() != ranks || incoming_bytes.size() != ranks)
    throw std::logic_error("ranks::exchange_known: " + std::to_string(outgoing.size()) + " buffers and " +
                           std::to_string(incoming_bytes.size()) + " sizes for " + std::to_string(ranks) + " ranks");
  if (outgoing[me].size() != incoming_bytes[me])
    throw std::logic_error("ranks::exchange_known: this rank sends itself " + std::to_string(outgoing[me].size()) +
                           " bytes but expects " + std::to_string(incoming_bytes[me]));
  std::vector<std::vector<std::byte>> incoming(ranks);
  incoming[me] = outgoing[me];  // a periodic image of its own grain
  if (ranks == 1) return incoming;
  const CallTimer timer(times.exchange_seconds, times.exchanges);
  // One tag for every such exchange: messages between two ranks arrive in the order sent, and every rank makes the
  // same sequence of exchanges.
  constexpr int kTag = 7;
  std::vector<MPI_Request> requests;
  std::vector<std::size_t> received_from;  // the ranks of the first requests, in order
  for (std::size_t r = 0; r < ranks; ++r) {
    if (r == me || incoming_bytes[r] == 0) continue;
    incoming[r].resize(incoming_bytes[r]);
    received_from.push_back(r);
    requests.emplace_back();
    check(MPI_Irecv(incoming[r].data(), to_int(incoming_bytes[r]), MPI_BYTE, static_cast<int>(r), kTag,
                    comm(), &requests.back()),
          "MPI_Irecv");
  }
  for (std::size_t r = 0; r < ranks; ++r) {
    if (r == me || outgoing[r].empty()) continue;
    requests.emplace_back();
    check(MPI_Isend(outgoing[r].data(), to_int(outgoing[r].size()), MPI_BYTE, static_cast<int>(r), kTag,
                    comm(), &requests.back()),
          "MPI_Isend");
  }
  std::vector<MPI_Status> statuses(requests.size());
  const int code = MPI_Waitall(static_cast<int>(requests.size()), requests.data(), statuses.data());
  check(code, "MPI_Waitall");
  // A shorter message than expected would leave the rest of the buffer as it was: the two sides disagree.
  for (std::size_t k = 0; k < received_from.size(); ++k) {
    int received = 0;
    check(MPI_Get_count(&statuses[k], MPI_BYTE, &received), "MPI_Get_count");
    if (static_cast<std::size_t>(received) != incoming_bytes[received_from[k]])
      throw std::logic_error("ranks::exchange_known: rank " + std::to_string(received_from[k]) + " sent " +
                             std::to_string(received) + " bytes where " +
                             std::to_string(incoming_bytes[received_from[k]]) + " were expected");
  }
  return incoming;
}

std::vector<std::vector<std::byte>> gather_at_root(const std::vector<std::byte>& mine) {
  const auto ranks = static_cast<std::size_t>(size());
  if (ranks == 1) return {mine};
  std::vector<std::vector<std::byte>> outgoing(ranks);
  outgoing[0] = mine;
  std::vector<std::vector<std::byte>> incoming = exchange(outgoing);
  if (rank() != 0) return {};
  return incoming;
}

std::vector<std::byte> broadcast_from_root(std::vector<std::byte> bytes) {
  if (size() == 1) return bytes;
  unsigned long long count = bytes.size();
  check(MPI_Bcast(&count, 1, MPI_UNSIGNED_LONG_LONG, 0, comm()), "MPI_Bcast");
  bytes.resize(static_cast<std::size_t>(count));
  check(MPI_Bcast(bytes.data(), to_int(bytes.size()), MPI_BYTE, 0, comm()), "MPI_Bcast");
  return bytes;
}

void barrier() {
  if (size() > 1) check(MPI_Barrier(comm()), "MPI_Barrier");
}

void abort(int code) {
  if (running()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // one rank, no MPI

bool mpi_built() { return false; }
void start_mpi() {}
int rank() { return 0; }
int size() { return 1; }
bool any(bool flag) { return flag; }
double max(double value) { return value; }
std::vector<double> sum_in_rank_order(const std::vector<double>& values) { return values; }
std::vector<double> gather_all(const std::vector<double>& values, std::vector<std::size_t>) { return values; }
std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& outgoing) {
  if (outgoing.size() != 1) throw std::logic_error("ranks::exchange: a build without MPI has one rank");
  return outgoing;
}
std::vector<std::vector<std::byte>> exchange_known(const std::vector<std::vector<std::byte>>& outgoing,
                                                   const std::vector<std::size_t>& incoming_bytes) {
  if (outgoing.size() != 1 || incoming_bytes.size() != 1 || outgoing[0].size() != incoming_bytes[0])
    throw std::logic_error("ranks::exchange_known: a build without MPI has one rank");
  return outgoing;
}
std::vector<std::vector<std::byte>> gather_at_root(const std::vector<std::byte>& mine) { return {mine}; }
std::vector<std::byte> broadcast_from_root(std::vector<std::byte> bytes) { return bytes; }
void barrier() {}
void abort(int code) { std::exit(code); }

#endif

}  // namespace riffle::ranks
