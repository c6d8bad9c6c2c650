#pragma once
// A value recomputed in a background thread while the previous one stays in
// use (the Interaction Graph's policies: PolicyService for the duel's
// competitive policy, CarryPolicyService for the carriers' collaborative
// ones). start() runs a job in a worker thread; a start while a job runs
// cancels that one (its progress callback returns false) and waits for it;
// a finished job's value replaces current() atomically, a failed one leaves
// current() as it was and is reported by wait().
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

#include "fray/core/progress.h"
#include "fray/core/result.h"

namespace fray::igraph {

template <class T>
class BackgroundRecompute {
public:
    using Job = std::function<Result<T>(const ProgressFn& progress)>;

    explicit BackgroundRecompute(std::shared_ptr<const T> initial) : current_(std::move(initial)) {}
    ~BackgroundRecompute() { stop(); }
    BackgroundRecompute(const BackgroundRecompute&) = delete;
    BackgroundRecompute& operator=(const BackgroundRecompute&) = delete;

    // The value in force now.
    std::shared_ptr<const T> current() const {
        const std::lock_guard<std::mutex> lock(mutex_);
        return current_;
    }
    // Cancels a job in flight, then runs `job` in the background.
    void start(Job job) {
        stop();
        running_ = true;
        worker_ = std::thread([this, job = std::move(job)] {
            auto v = job(cancelWhen(cancel_));
            {
                const std::lock_guard<std::mutex> lock(mutex_);
                if (v) {
                    current_ = std::make_shared<const T>(std::move(*v));
                    last_ = {};
                } else {
                    last_ = v.error();
                }
            }
            running_ = false;
        });
    }
    bool busy() const { return running_.load(); }
    // Waits until no job runs; the last error (if any) of a finished one.
    Status wait() {
        if (worker_.joinable()) worker_.join();
        const std::lock_guard<std::mutex> lock(mutex_);
        return last_;
    }
    // Cancels a job in flight and waits for it.
    void stop() {
        cancel_ = true;
        if (worker_.joinable()) worker_.join();
        cancel_ = false;
    }

private:
    mutable std::mutex mutex_;
    std::shared_ptr<const T> current_;
    std::thread worker_;
    std::atomic<bool> cancel_{false}, running_{false};
    Status last_;
};

}  // namespace fray::igraph
