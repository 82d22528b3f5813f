// The ranks of an MPI job (Open MPI) as the render driver's Cluster. Rank 0 hands out runs of
// frames from a thread of its own while it renders too, so that a rank asking for work waits
// for a message, not for rank 0's frame; the thread polls with short sleeps rather than
// blocking in MPI, whose blocking receive spins and would take a core from the render. Only
// that thread calls MPI while it runs (MPI_THREAD_SERIALIZED).

#include "distributed/cluster.h"
#include "distributed/frame_handout.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

namespace dynrt::cli {

namespace {

enum Tag : int { kAsk = 1, kRun = 2, kRecord = 3 };

class MpiCluster final : public Cluster {
public:
    MpiCluster() {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        // Open MPI offers it; an MPI library that does not cannot run the hand-out thread.
        if (provided < MPI_THREAD_SERIALIZED) {
            fail("rank " + std::to_string(rank_) + ": the MPI library does not offer "
                 "MPI_THREAD_SERIALIZED, which rank 0's hand-out thread needs");
        }
    }
    ~MpiCluster() override {
        if (dispatcher_.joinable()) dispatcher_.join();
        MPI_Finalize();
    }

    int rank() const override { return rank_; }
    int size() const override { return size_; }

    std::vector<int> broadcast(const std::vector<int>& values) override {
        int count = int(values.size());
        MPI_Bcast(&count, 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::vector<int> out = rank_ == 0 ? values : std::vector<int>(std::size_t(count));
        MPI_Bcast(out.data(), count, MPI_INT, 0, MPI_COMM_WORLD);
        return out;
    }

    void start_handout(const std::vector<int>& todo,
                       std::function<void(const std::string&)> on_record) override {
        if (rank_ != 0) return;
        handout_.emplace(todo, size_);
        on_record_ = std::move(on_record);
        if (size_ > 1) dispatcher_ = std::thread([this] { dispatch(); });
    }

    std::vector<int> next_run() override {
        if (rank_ == 0) {
            const std::lock_guard lock(mutex_);
            return handout_->take();
        }
        MPI_Send(nullptr, 0, MPI_INT, 0, kAsk, MPI_COMM_WORLD);
        MPI_Status status;
        MPI_Probe(0, kRun, MPI_COMM_WORLD, &status);
        int count = 0;
        MPI_Get_count(&status, MPI_INT, &count);
        std::vector<int> run(static_cast<std::size_t>(count));
        MPI_Recv(run.data(), count, MPI_INT, 0, kRun, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        return run;
    }

    void send_record(const std::string& record) override {
        if (rank_ == 0) {
            const std::lock_guard lock(mutex_);
            on_record_(record);
            return;
        }
        MPI_Send(record.data(), int(record.size()), MPI_CHAR, 0, kRecord, MPI_COMM_WORLD);
    }

    void finish_handout() override {
        if (rank_ == 0 && dispatcher_.joinable()) dispatcher_.join();
    }

    std::vector<float> gather(const std::vector<float>& mine) override {
        const int bytes = int(mine.size() * sizeof(float));
        std::vector<int> counts(rank_ == 0 ? std::size_t(size_) : 0);
        MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::vector<int> offsets(counts.size());
        std::size_t total = 0;
        for (std::size_t r = 0; r < counts.size(); ++r) {
            offsets[r] = int(total);
            total += std::size_t(counts[r]);
        }
        std::vector<float> all(total / sizeof(float));
        // Bytes, not MPI_FLOAT: the object and primitive ids travel as float bit patterns.
        MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(),
                    MPI_BYTE, 0, MPI_COMM_WORLD);
        return all;
    }

    std::vector<double> gather_figures(const std::vector<double>& mine) override {
        std::vector<double> all(rank_ == 0 ? mine.size() * std::size_t(size_) : 0);
        MPI_Gather(mine.data(), int(mine.size()), MPI_DOUBLE, all.data(), int(mine.size()),
                   MPI_DOUBLE, 0, MPI_COMM_WORLD);
        return all;
    }

    [[noreturn]] void fail(const std::string& message) override {
        // One write: under mpirun each write is forwarded on its own, and Open MPI's abort
        // notice would otherwise land in the middle of the line.
        std::cerr << ("dynrt: error: " + message + "\n") << std::flush;
        MPI_Abort(MPI_COMM_WORLD, 1);
        std::abort();  // MPI_Abort does not return
    }

private:
    /// Rank 0's hand-out thread: answers asks and takes records until every other rank has
    /// been told that nothing is left.
    void dispatch() {
        try {
            while (finished_ranks_ < size_ - 1) {
                if (!serve_one()) std::this_thread::sleep_for(std::chrono::microseconds(100));
            }
        } catch (const std::exception& e) {
            fail(std::string("rank 0 (hand-out): ") + e.what());
        }
    }

    /// Handles one ask or record; returns false when none was there.
    bool serve_one() {
        MPI_Status status;
        int arrived = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
        if (!arrived) return false;
        if (status.MPI_TAG == kAsk) {
            MPI_Recv(nullptr, 0, MPI_INT, status.MPI_SOURCE, kAsk, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            std::vector<int> run;
            {
                const std::lock_guard lock(mutex_);
                run = handout_->take();
            }
            MPI_Send(run.data(), int(run.size()), MPI_INT, status.MPI_SOURCE, kRun, MPI_COMM_WORLD);
            if (run.empty()) ++finished_ranks_;
        } else if (status.MPI_TAG == kRecord) {
            int length = 0;
            MPI_Get_count(&status, MPI_CHAR, &length);
            std::string record(std::size_t(length), '\0');
            MPI_Recv(record.data(), length, MPI_CHAR, status.MPI_SOURCE, kRecord, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            const std::lock_guard lock(mutex_);
            on_record_(record);
        } else {
            throw std::logic_error("unexpected MPI message, tag " + std::to_string(status.MPI_TAG));
        }
        return true;
    }

    int rank_ = 0;
    int size_ = 1;
    std::optional<FrameHandout> handout_;
    std::function<void(const std::string&)> on_record_;
    std::mutex mutex_;
    std::thread dispatcher_;
    int finished_ranks_ = 0;
};

}  // namespace

std::unique_ptr<Cluster> mpi_cluster() { return std::make_unique<MpiCluster>(); }

}  // namespace dynrt::cli
