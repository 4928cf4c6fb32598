#include "drone/video/frame_pool.hpp"

#include <new>

namespace gs::video {
namespace {
constexpr size_t kAutoStep = 0x7fffffff;  // OpenCV's CV_AUTOSTEP (core/types_c.h)
}  // namespace

// One buffer and the OpenCV bookkeeping of the Mat that holds it, built in place when the buffer
// is handed out and destroyed when it comes back: no allocation per frame.
struct FramePool::Slot {
    uchar* memory = nullptr;
    std::size_t capacity = 0;
    alignas(cv::UMatData) unsigned char bookkeeping[sizeof(cv::UMatData)];

    ~Slot() { cv::fastFree(memory); }
};

class FramePool::Allocator final : public cv::MatAllocator {
public:
    explicit Allocator(FramePool& pool) : pool_(pool) {}

    cv::UMatData* allocate(int dims, const int* sizes, int type, void* data0, size_t* step,
                           cv::AccessFlag, cv::UMatUsageFlags) const override {
        // Steps as OpenCV's own allocator computes them (continuous rows).
        size_t total = CV_ELEM_SIZE(type);
        for (int i = dims - 1; i >= 0; i--) {
            if (step != nullptr) {
                if (data0 != nullptr && step[i] != kAutoStep) {
                    CV_Assert(total <= step[i]);
                    total = step[i];
                } else {
                    step[i] = total;
                }
            }
            total *= static_cast<size_t>(sizes[i]);
        }
        pool_.holders_.fetch_add(1, std::memory_order_relaxed);
        Slot* slot = data0 == nullptr ? take_slot() : nullptr;
        cv::UMatData* u = nullptr;
        if (slot != nullptr) {
            if (slot->capacity < total) {  // the first frame of this size (or a larger one)
                cv::fastFree(slot->memory);
                slot->memory = static_cast<uchar*>(cv::fastMalloc(total));
                slot->capacity = total;
            }
            u = new (slot->bookkeeping) cv::UMatData(this);
            u->data = u->origdata = slot->memory;
            u->userdata = slot;
        } else {
            u = new cv::UMatData(this);
            u->data = u->origdata = data0 != nullptr ? static_cast<uchar*>(data0)
                                                     : static_cast<uchar*>(cv::fastMalloc(total));
            if (data0 != nullptr) u->flags |= cv::UMatData::USER_ALLOCATED;
        }
        u->size = total;
        return u;
    }

    bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override {
        return u != nullptr;
    }

    // The last Mat header referring to the buffer went away: the buffer is free again.
    void deallocate(cv::UMatData* u) const override {
        if (u == nullptr) return;
        CV_Assert(u->urefcount == 0 && u->refcount == 0);
        if (auto* slot = static_cast<Slot*>(u->userdata)) {
            u->~UMatData();
            pool_.taken_.release(static_cast<std::size_t>(slot - pool_.slots_.get()));
        } else {
            if (!(u->flags & cv::UMatData::USER_ALLOCATED)) cv::fastFree(u->origdata);
            delete u;
        }
        pool_.drop_holder();  // may delete the pool (and this allocator): nothing after it
    }

private:
    // A free buffer, or nullptr when every one is out (counted by the slot set).
    Slot* take_slot() const {
        const std::optional<std::size_t> i = pool_.taken_.acquire();
        return i ? &pool_.slots_[*i] : nullptr;
    }

    FramePool& pool_;
};

std::shared_ptr<FramePool> FramePool::create(std::size_t slots) {
    return std::shared_ptr<FramePool>(new FramePool(slots), [](FramePool* p) { p->drop_holder(); });
}

FramePool::FramePool(std::size_t slots)
    : taken_(slots),
      slots_(new Slot[taken_.capacity()]),
      allocator_(std::make_unique<Allocator>(*this)) {}

FramePool::~FramePool() = default;

void FramePool::drop_holder() {
    if (holders_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
}

cv::Mat FramePool::acquire() {
    cv::Mat m;
    m.allocator = allocator_.get();
    return m;
}

}  // namespace gs::video
