// A "cluster" of this process alone: the render driver's distributed paths with one rank, for
// `--resume` without mpirun and for a dynrt built without MPI.

#include "distributed/cluster.h"
#include "distributed/frame_handout.h"

#include <cstdlib>
#include <optional>
#include <stdexcept>

namespace dynrt::cli {

namespace {

class LocalCluster final : public Cluster {
public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::vector<int> broadcast(const std::vector<int>& values) override { return values; }
    void start_handout(const std::vector<int>& todo,
                       std::function<void(const std::string&)> on_record) override {
        handout_.emplace(todo, 1);
        on_record_ = std::move(on_record);
    }
    std::vector<int> next_run() override { return handout_->take(); }
    void send_record(const std::string& record) override { on_record_(record); }
    void finish_handout() override {}
    std::vector<float> gather(const std::vector<float>& mine) override { return mine; }
    std::vector<double> gather_figures(const std::vector<double>& mine) override { return mine; }
    [[noreturn]] void fail(const std::string& message) override { throw std::runtime_error(message); }

private:
    std::optional<FrameHandout> handout_;
    std::function<void(const std::string&)> on_record_;
};

}  // namespace

std::unique_ptr<Cluster> local_cluster() { return std::make_unique<LocalCluster>(); }

bool started_by_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

#ifndef DYNRT_HAVE_MPI
std::unique_ptr<Cluster> mpi_cluster() { return nullptr; }
#endif

}  // namespace dynrt::cli
