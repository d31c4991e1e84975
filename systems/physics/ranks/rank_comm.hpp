#pragma once
// The MPI ranks of a distributed run, as the systems see them: who this process is, and the few collective
// operations the grains' decomposition needs (systems/physics/ranks/grain_ranks.hpp). Everything goes over
// MPI_COMM_WORLD. A build without MPI, or a process started without mpirun, is rank 0 of 1 and every operation is
// the identity, so one-rank code calls these without asking.
//
// Reductions that feed the physics (a sum of energies, the largest displacement) are taken in rank order on every
// rank (gather, then add in order), never with MPI_Allreduce's unspecified order: a run is reproducible for a given
// rank count.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace riffle::ranks {

/// True when riffle was built with MPI (RIFFLE_HYPRE found hypre and MPI).
bool mpi_built();
/// Starts MPI (MPI_THREAD_SERIALIZED: the exchanges run on whichever oneTBB thread runs the system, one at a time),
/// once per process, and finalises it at exit if it started it. A no-op without MPI.
void start_mpi();
/// This process's rank and the rank count; 0 and 1 before start_mpi or without MPI.
int rank();
int size();
/// True if the run is spread over more than one rank.
inline bool distributed() { return size() > 1; }

/// True on every rank if `flag` is true on any.
bool any(bool flag);
/// The largest `value` over the ranks, on every rank (max is exact in any order).
double max(double value);
/// Each rank's `values` (the same length on every rank) summed element by element in rank order, on every rank.
std::vector<double> sum_in_rank_order(const std::vector<double>& values);
/// Every rank's `values` concatenated in rank order, on every rank. With every rank's length known beforehand
/// (counts[r]: rank r's; counts[rank()] == values.size()) one MPI_Allgatherv; without, the lengths are gathered first.
std::vector<double> gather_all(const std::vector<double>& values, std::vector<std::size_t> counts = {});

/// Sends outgoing[r] to rank r (outgoing.size() == size(); an empty buffer sends nothing) and returns what each rank
/// sent here, indexed by the sender. Collective: every rank calls it.
std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& outgoing);

/// The same as exchange when both sides already know how much each pair sends (incoming_bytes[r]: the bytes rank r
/// sends here): messages go only between the ranks that have something for each other, point to point, with no
/// count exchanged and no call that every rank joins. What a decomposed run does every sub-step, where a rank
/// talks to its few neighbours whatever the rank count. Collective over the ranks that send to or receive from each
/// other.
std::vector<std::vector<std::byte>> exchange_known(const std::vector<std::vector<std::byte>>& outgoing,
                                                   const std::vector<std::size_t>& incoming_bytes);
/// Every rank's bytes, in rank order, at rank 0 (empty elsewhere). Collective.
std::vector<std::vector<std::byte>> gather_at_root(const std::vector<std::byte>& mine);
/// Rank 0's bytes on every rank. Collective.
std::vector<std::byte> broadcast_from_root(std::vector<std::byte> bytes);

/// Waits for every rank.
void barrier();

/// The time this process has spent in the calls above, waiting included (a rank that waits for a slower one spends
/// it here): what a run over ranks reports beside its stepping time, to tell the work's imbalance from the talk.
struct CallTimes {
  double exchange_seconds = 0.0;  ///< exchange and the gathers
  double reduce_seconds = 0.0;    ///< any, max and the sums
  std::uint64_t exchanges = 0, reductions = 0;
};
const CallTimes& call_times();

/// Ends every rank at once with `code` (MPI_Abort): for a rank that cannot go on while the others wait for it in an
/// exchange. Without MPI, std::exit(code).
[[noreturn]] void abort(int code);

}  // namespace riffle::ranks
