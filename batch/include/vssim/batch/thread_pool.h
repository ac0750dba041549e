// A small fixed pool of threads for data-parallel loops: parallelFor(n, fn)
// runs fn(0) .. fn(n - 1), each exactly once, spread over the threads, and
// returns when all are done. The calling thread is one of them: a pool of
// `threads` starts threads - 1 workers, and a pool of one (or a loop of one
// index) runs on the caller alone, with no hand-over (a step of one world
// costs no thread wake-up). Workers sleep on a condition variable between
// loops (no busy-waiting) and are joined by the destructor.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vssim {

class ThreadPool {
public:
    // `threads` threads, the caller's included; 0 means
    // std::thread::hardware_concurrency() (at least 1). Throws
    // std::invalid_argument for a negative count.
    explicit ThreadPool(int threads = 0);
    ~ThreadPool();  // wakes the workers and joins them
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    // The threads a loop runs on: the workers and the caller.
    int size() const { return static_cast<int>(workers_.size()) + 1; }

    // Inside fn of a parallelFor: which of the pool's threads runs this call,
    // 0 (the caller) to size() - 1; always 0 for a loop run serially. (So
    // that fn can use per-thread scratch without locking.) 0 elsewhere.
    static int threadIndex();

    // Calls fn(i) for every i in [0, n), each exactly once, on the caller and
    // the workers, in no particular order, and blocks until every call has
    // returned.
    // When calls throw, every index is still run, and the exception of the
    // lowest index that threw is rethrown here (the same one whatever the
    // thread count). n = 0 returns at once. Calls from several threads are
    // served one loop at a time; a call from inside fn (on a worker of this
    // pool) runs its loop serially on that worker rather than deadlocking.
    void parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

private:
    void workerLoop();
    // The loop on the calling thread alone, with the same error rule.
    static void runSerially(std::size_t n, const std::function<void(std::size_t)>& fn);
    // Runs indices of the current loop until none are left; returns how many it ran.
    std::size_t runIndices();

    std::vector<std::thread> workers_;
    std::mutex loopMutex_;  // one parallelFor at a time
    std::mutex mutex_;      // guards everything below
    std::condition_variable wake_;  // workers: a new loop, or shutting down
    std::condition_variable done_;  // the caller: the loop has finished
    bool stopping_ = false;
    // The current loop.
    std::uint64_t generation_ = 0;  // counts loops; a worker joins each one once
    bool active_ = false;           // a loop is running (workers may join it)
    const std::function<void(std::size_t)>* fn_ = nullptr;
    std::size_t n_ = 0;
    std::atomic<std::size_t> next_{0};  // the next index to hand out (taken by workers inside the loop)
    std::size_t finished_ = 0;  // indices run
    int busy_ = 0;              // workers inside the loop (the caller not counted)
    std::exception_ptr error_;  // the exception of the lowest index that threw
    std::size_t errorIndex_ = 0;
};

}  // namespace vssim
