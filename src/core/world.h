// The processes a render is split over: MPI's ranks when the program runs under mpirun
// (distributed/mpi_world.h makes that world), one process otherwise (local_world()). The render
// loop, the film and the render job see only this interface: which rank this is, how many there
// are, and the few collective operations a render needs. Every rank must call the collectives in
// the same order (they block until all have); rank 0 is the root of reductions and broadcasts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ml {

class World {
public:
    virtual ~World() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    bool root() const { return rank() == 0; }

    // Element-wise sums of every rank's `data` into rank 0's (other ranks' data is left as it
    // was). The order in which ranks' values are added is MPI's; a value that only one rank has
    // non-zero (the other ranks add +0) arrives exactly.
    virtual void reduce_sum(double* data, size_t n) = 0;
    virtual void reduce_sum(float* data, size_t n) = 0;
    // The sum, minimum or maximum over the ranks, on every rank.
    virtual int64_t all_sum(int64_t v) = 0;
    virtual int64_t all_min(int64_t v) = 0;
    virtual double all_max(double v) = 0;
    // Rank 0's bytes to every rank.
    virtual void broadcast(void* data, size_t bytes) = 0;
    // Every rank's value, in rank order, on rank 0 (empty elsewhere).
    virtual std::vector<double> gather(double v) = 0;
    // Waits until every rank has come here.
    virtual void barrier() = 0;
    // Ends every rank's process with `message` on this rank's stderr and exit code `code`
    // (MPI_Abort): an error on one rank must not leave the others waiting in a collective.
    [[noreturn]] virtual void abort(const std::string& message, int code) = 0;

    // Rank 0's decision, on every rank (e.g. "the time limit is spent"): a broadcast.
    bool root_decides(bool v) {
        char c = v ? 1 : 0;
        broadcast(&c, 1);
        return c != 0;
    }

    // Bytes this rank gave to reductions (its whole buffer per reduce_sum) and to broadcasts (as
    // the root, or received) since the world was made: the traffic --stats reports.
    uint64_t bytes_reduced() const { return m_bytes_reduced; }
    uint64_t bytes_broadcast() const { return m_bytes_broadcast; }

protected:
    uint64_t m_bytes_reduced = 0, m_bytes_broadcast = 0;
};

// One process, no MPI: rank 0 of 1; the collectives are the identity and cost nothing.
class LocalWorld final : public World {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    void reduce_sum(double*, size_t) override {}
    void reduce_sum(float*, size_t) override {}
    int64_t all_sum(int64_t v) override { return v; }
    int64_t all_min(int64_t v) override { return v; }
    double all_max(double v) override { return v; }
    void broadcast(void*, size_t) override {}
    std::vector<double> gather(double v) override { return {v}; }
    void barrier() override {}
    [[noreturn]] void abort(const std::string& message, int code) override;
};

// The one process's world, for renders that are not given one.
World& local_world();

}  // namespace ml
