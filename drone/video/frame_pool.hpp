#pragma once
// A fixed set of image buffers for decoded video frames, reused frame after frame.
//
// The decoder writes into the cv::Mat that acquire() returns; the frame then travels as an
// ordinary cv::Mat header (FrameSample::image) to every consumer. A buffer is acquired when such a
// Mat allocates its pixels (the pool is its cv::MatAllocator) and released when the last header
// referring to it goes away (OpenCV calls the allocator's deallocate()): the pool keeps its own
// record of which buffer is out (a core::SlotSet, drone/core/object_pool.hpp), and never reads
// OpenCV's or a shared_ptr's reference count to decide. When every buffer is out, a frame gets
// heap memory instead (counted in exhausted()).
//
// Steady state allocates nothing: buffers and their OpenCV bookkeeping (UMatData) live in the
// slots. Thread-safe: buffers are acquired on one thread (the decoder's) and released on any.
// The pool outlives its owner while frames are still out (it deletes itself with the last one).

#include "drone/core/object_pool.hpp"

#include <opencv2/core.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace gs::video {

class FramePool {
public:
    // `slots` buffers (each grows to the largest frame it held, then stays).
    static std::shared_ptr<FramePool> create(std::size_t slots);
    ~FramePool();
    FramePool(const FramePool&) = delete;
    FramePool& operator=(const FramePool&) = delete;

    // An empty Mat whose create() takes a free buffer of this pool. Decoding into it costs no
    // allocation once the buffer has held a frame of that size.
    cv::Mat acquire();

    std::size_t slots() const { return taken_.capacity(); }
    std::size_t in_use() const { return taken_.in_use(); }  // buffers currently held by some Mat
    std::uint64_t exhausted() const { return taken_.exhausted(); }

private:
    class Allocator;
    struct Slot;
    struct Shared;
    explicit FramePool(std::size_t slots);

    SlotSet taken_;  // which buffers are out
    std::unique_ptr<Slot[]> slots_;
    std::unique_ptr<Allocator> allocator_;
    // The owner's handle plus one per buffer out: the last one to go deletes the pool.
    std::atomic<std::size_t> holders_{1};
    void drop_holder();
    friend class Allocator;
};

}  // namespace gs::video
