#include "vssim/batch/thread_pool.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace vssim {

namespace {
// The pool whose worker this thread is, if any (a nested parallelFor runs serially).
thread_local const ThreadPool* tCurrentPool = nullptr;
// Which of its pool's threads this one is (threadIndex()).
thread_local int tThreadIndex = 0;
}  // namespace

int ThreadPool::threadIndex() { return tThreadIndex; }

ThreadPool::ThreadPool(int threads) {
    if (threads < 0)
        throw std::invalid_argument("ThreadPool: the thread count must be 0 (all cores) or more, not " +
                                    std::to_string(threads));
    if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    workers_.reserve(static_cast<std::size_t>(threads - 1));
    try {
        for (int i = 1; i < threads; ++i)
            workers_.emplace_back([this, i] {
                tThreadIndex = i;
                workerLoop();
            });
    } catch (...) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : workers_) t.join();
        throw;
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void ThreadPool::runSerially(std::size_t n, const std::function<void(std::size_t)>& fn) {
    std::exception_ptr first;
    for (std::size_t i = 0; i < n; ++i) {
        try {
            fn(i);
        } catch (...) {
            if (!first) first = std::current_exception();
        }
    }
    if (first) std::rethrow_exception(first);
}

void ThreadPool::parallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (n == 0) return;
    // No workers, or one index: nothing to share. Called from one of our own
    // workers (or from fn on the caller): the others may all be waiting for
    // this one, so the loop runs here.
    if (workers_.empty() || n == 1 || tCurrentPool == this) {
        if (tCurrentPool == this) {  // nested: keep this thread's index
            runSerially(n, fn);
            return;
        }
        const int outerIndex = tThreadIndex;
        tThreadIndex = 0;
        try {
            runSerially(n, fn);
        } catch (...) {
            tThreadIndex = outerIndex;
            throw;
        }
        tThreadIndex = outerIndex;
        return;
    }
    std::lock_guard<std::mutex> loop(loopMutex_);
    std::unique_lock<std::mutex> lock(mutex_);
    fn_ = &fn;
    n_ = n;
    next_.store(0, std::memory_order_relaxed);
    finished_ = 0;
    error_ = nullptr;
    errorIndex_ = 0;
    active_ = true;
    ++generation_;
    lock.unlock();
    wake_.notify_all();
    // The caller runs indices too, marked as one of the pool's threads (a
    // nested parallelFor from fn runs serially).
    const ThreadPool* outer = tCurrentPool;
    const int outerIndex = tThreadIndex;
    tCurrentPool = this;
    tThreadIndex = 0;
    const std::size_t ran = runIndices();
    tCurrentPool = outer;
    tThreadIndex = outerIndex;
    lock.lock();
    finished_ += ran;
    // Done when every index has run and no worker is still inside the loop
    // (one that is could otherwise take an index of the next loop).
    done_.wait(lock, [this] { return finished_ == n_ && busy_ == 0; });
    active_ = false;
    fn_ = nullptr;
    std::exception_ptr error = error_;
    error_ = nullptr;
    lock.unlock();
    if (error) std::rethrow_exception(error);
}

std::size_t ThreadPool::runIndices() {
    std::size_t ran = 0;
    for (;;) {
        const std::size_t i = next_.fetch_add(1, std::memory_order_relaxed);
        if (i >= n_) return ran;  // n_ does not change while this worker is busy
        try {
            (*fn_)(i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!error_ || i < errorIndex_) {
                error_ = std::current_exception();
                errorIndex_ = i;
            }
        }
        ++ran;
    }
}

void ThreadPool::workerLoop() {
    tCurrentPool = this;
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
        if (stopping_) return;
        seen = generation_;
        if (!active_) continue;  // woke after that loop had already finished
        ++busy_;
        lock.unlock();
        const std::size_t ran = runIndices();
        lock.lock();
        finished_ += ran;
        --busy_;
        if (busy_ == 0 && finished_ == n_) done_.notify_one();
    }
}

}  // namespace vssim
