#include "distributed/mpi_world.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.h"

#if MANYLIGHT_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <climits>
#endif

namespace ml {

namespace {

int env_int(const char* name) {
    const char* v = std::getenv(name);
    return v ? std::atoi(v) : 0;
}

#if MANYLIGHT_HAVE_MPI

// MPI counts are ints: long buffers go in pieces of this many elements.
constexpr size_t kMaxPiece = size_t(1) << 28;

class MpiWorld final : public World {
public:
    MpiWorld(int* argc, char*** argv) {
        int provided = 0;
        // Only the main thread calls MPI; TBB's workers never do.
        MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    }
    ~MpiWorld() override {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }
    int rank() const override { return m_rank; }
    int size() const override { return m_size; }
    void reduce_sum(double* data, size_t n) override { reduce(data, n, MPI_DOUBLE); }
    void reduce_sum(float* data, size_t n) override { reduce(data, n, MPI_FLOAT); }
    int64_t all_sum(int64_t v) override { return all(v, MPI_SUM); }
    int64_t all_min(int64_t v) override { return all(v, MPI_MIN); }
    double all_max(double v) override {
        double r = 0;
        MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        return r;
    }
    void broadcast(void* data, size_t bytes) override {
        m_bytes_broadcast += bytes;
        for (size_t off = 0; off < bytes; off += kMaxPiece)
            MPI_Bcast(static_cast<char*>(data) + off, int(std::min(kMaxPiece, bytes - off)),
                      MPI_BYTE, 0, MPI_COMM_WORLD);
    }
    std::vector<double> gather(double v) override {
        std::vector<double> all(m_rank == 0 ? size_t(m_size) : 0);
        MPI_Gather(&v, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
        return all;
    }
    void barrier() override { MPI_Barrier(MPI_COMM_WORLD); }
    [[noreturn]] void abort(const std::string& message, int code) override {
        std::fprintf(stderr, "%s\n", message.c_str());
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, code);
        std::_Exit(code);  // MPI_Abort does not return; should it, this process still ends
    }

private:
    template <typename T>
    void reduce(T* data, size_t n, MPI_Datatype type) {
        m_bytes_reduced += n * sizeof(T);
        for (size_t off = 0; off < n; off += kMaxPiece) {
            int count = int(std::min(kMaxPiece, n - off));
            if (m_rank == 0)
                MPI_Reduce(MPI_IN_PLACE, data + off, count, type, MPI_SUM, 0, MPI_COMM_WORLD);
            else
                MPI_Reduce(data + off, nullptr, count, type, MPI_SUM, 0, MPI_COMM_WORLD);
        }
    }
    int64_t all(int64_t v, MPI_Op op) {
        int64_t r = 0;
        MPI_Allreduce(&v, &r, 1, MPI_INT64_T, op, MPI_COMM_WORLD);
        return r;
    }
    int m_rank = 0, m_size = 1;
};

#endif

}  // namespace

bool mpi_built() { return MANYLIGHT_HAVE_MPI != 0; }

int launched_ranks() {
    int n = env_int("OMPI_COMM_WORLD_SIZE");
    if (n < 1) n = env_int("PMI_SIZE");
    return n < 1 ? 1 : n;
}

World& process_world(int* argc, char*** argv) {
    if (launched_ranks() <= 1) return local_world();
#if MANYLIGHT_HAVE_MPI
    static MpiWorld world(argc, argv);
    return world;
#else
    throw UsageError(std::to_string(launched_ranks()) +
                     " processes were launched, but this manylight was built without MPI "
                     "(cmake -DMANYLIGHT_MPI=ON with libopenmpi-dev installed); run it without "
                     "mpirun");
#endif
}

}  // namespace ml
