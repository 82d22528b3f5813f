#pragma once
// The processes a render is spread over (`dynrt render --distribute`): an MPI job's ranks
// (mpi_cluster.cpp, built when Open MPI is installed) or this process alone (local_cluster.cpp,
// for every render not started by mpirun, and for a dynrt built without MPI). The render
// driver (distributed_render.cpp), the one frame loop of every render, sees only this
// interface.

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::cli {

class Cluster {
public:
    virtual ~Cluster() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;

    /// Rank 0's `values` on every rank (the others' argument is ignored).
    virtual std::vector<int> broadcast(const std::vector<int>& values) = 0;

    // ---- Frames handed out (`--distribute frames`) ----
    /// Every rank calls it once before next_run: rank 0 starts handing out `todo` (the others'
    /// is ignored) in runs (FrameHandout), and calls `on_record` with each record a rank sends
    /// (one call at a time, on any thread of rank 0).
    virtual void start_handout(const std::vector<int>& todo,
                               std::function<void(const std::string&)> on_record) = 0;
    /// This rank's next run of frames; empty once none is left.
    virtual std::vector<int> next_run() = 0;
    /// Sends a finished frame's record to rank 0's `on_record`.
    virtual void send_record(const std::string& record) = 0;
    /// Rank 0: returns once every rank has finished and every record has been handled.
    virtual void finish_handout() = 0;

    // ---- A frame's tiles shared (`--distribute tiles`) ----
    /// Every rank's `mine`, concatenated in rank order, on rank 0 (empty on the others).
    virtual std::vector<float> gather(const std::vector<float>& mine) = 0;
    /// The same for a few figures per rank (each rank sends as many).
    virtual std::vector<double> gather_figures(const std::vector<double>& mine) = 0;

    /// Stops every process after this one failed: writes `message` to stderr and ends the
    /// job (MPI_Abort), or, alone, throws it as std::runtime_error.
    [[noreturn]] virtual void fail(const std::string& message) = 0;
};

/// This process alone.
std::unique_ptr<Cluster> local_cluster();

/// True when this process was started by mpirun (Open MPI's environment says so).
bool started_by_mpirun();

/// The MPI job this process belongs to (MPI_Init); nullptr when dynrt was built without MPI.
std::unique_ptr<Cluster> mpi_cluster();

}  // namespace dynrt::cli
