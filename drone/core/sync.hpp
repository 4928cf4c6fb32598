#pragma once
// The only two ways threads share data in ardrone-gs: a latest-value slot (telemetry, video,
// decisions: readers want the newest, never a backlog) and a bounded queue (commands, records to
// disk: every item matters, but memory is bounded and overflow is counted, never silent).

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace gs::inline core {

// Holds the newest value and a generation counter. Writers publish; readers copy only when the
// generation moved (PX4 uORB-style), so a reader never sees a torn value.
template <class T>
class LatestValue {
public:
    void publish(T v) {
        std::lock_guard lk(m_);
        value_ = std::move(v);
        ++generation_;
    }
    // Read-modify-write under the slot's lock (for rare updates such as subscriber lists).
    template <class F>
    void update(F&& f) {
        std::lock_guard lk(m_);
        f(value_);
        ++generation_;
    }
    // Copies the value into `out` when it is newer than `*seen_generation`; updates the generation.
    bool read_if_newer(std::uint64_t& seen_generation, T& out) const {
        std::lock_guard lk(m_);
        if (generation_ == seen_generation || generation_ == 0) return false;
        out = value_;
        seen_generation = generation_;
        return true;
    }
    // Copy of the latest value (std::nullopt before the first publish).
    std::optional<T> latest() const {
        std::lock_guard lk(m_);
        if (generation_ == 0) return std::nullopt;
        return value_;
    }
    std::uint64_t generation() const {
        std::lock_guard lk(m_);
        return generation_;
    }

private:
    mutable std::mutex m_;
    T value_{};
    std::uint64_t generation_ = 0;
};

enum class QueueFull { RejectNew, DropOldest };

// Multi-producer multi-consumer FIFO with a fixed capacity. Overflow follows the policy and is
// counted; close() wakes every waiter (pop returns nullopt once closed and drained).
template <class T>
class BoundedQueue {
public:
    explicit BoundedQueue(std::size_t capacity, QueueFull policy = QueueFull::RejectNew)
        : capacity_(capacity == 0 ? 1 : capacity), policy_(policy) {}

    // Returns false when the item was not queued (queue closed, or full with RejectNew).
    bool push(T v) {
        {
            std::lock_guard lk(m_);
            if (closed_) {
                ++dropped_;
                return false;
            }
            if (q_.size() >= capacity_) {
                ++dropped_;
                if (policy_ == QueueFull::RejectNew) return false;
                q_.pop_front();
            }
            q_.push_back(std::move(v));
            high_water_ = std::max(high_water_, q_.size());
        }
        cv_.notify_one();
        return true;
    }

    std::optional<T> try_pop() {
        std::lock_guard lk(m_);
        return pop_locked();
    }

    // Waits up to `timeout` for an item; nullopt on timeout or when closed and empty.
    template <class Rep, class Period>
    std::optional<T> pop_for(std::chrono::duration<Rep, Period> timeout) {
        std::unique_lock lk(m_);
        cv_.wait_for(lk, timeout, [&] { return !q_.empty() || closed_; });
        return pop_locked();
    }

    void close() {
        {
            std::lock_guard lk(m_);
            closed_ = true;
        }
        cv_.notify_all();
    }

    // Opens a closed queue again (a restarted link reuses its queues); queued items are dropped.
    void reopen() {
        std::lock_guard lk(m_);
        q_.clear();
        closed_ = false;
    }

    bool closed() const {
        std::lock_guard lk(m_);
        return closed_;
    }
    std::size_t size() const {
        std::lock_guard lk(m_);
        return q_.size();
    }
    std::size_t capacity() const { return capacity_; }
    std::uint64_t dropped() const {
        std::lock_guard lk(m_);
        return dropped_;
    }
    std::size_t high_water() const {
        std::lock_guard lk(m_);
        return high_water_;
    }

private:
    std::optional<T> pop_locked() {
        if (q_.empty()) return std::nullopt;
        T v = std::move(q_.front());
        q_.pop_front();
        return v;
    }

    mutable std::mutex m_;
    std::condition_variable cv_;
    std::deque<T> q_;
    const std::size_t capacity_;
    const QueueFull policy_;
    bool closed_ = false;
    std::uint64_t dropped_ = 0;
    std::size_t high_water_ = 0;
};

}  // namespace gs::inline core
