#pragma once
// Pools with explicit acquire and release: a fixed number of slots, taken and given back by the
// pool's own record of which are out, never by peeking at a reference count (docs/architecture.md
// "Threads during a live flight", Pools). Steady state allocates nothing. Exhaustion is counted,
// never silent: acquire() then returns nothing and the caller decides (a heap object instead).
//
//   SlotSet        which of N slots are out: acquire() -> index or nothing, release(index).
//                  The video frame pool (drone/video/frame_pool.hpp) keeps its buffers with it.
//   ObjectPool<T>  N reusable objects handed out as shared_ptr<T>: the object goes back to the
//                  pool (release) when the last copy of the pointer is dropped, on any thread.
//                  The object keeps what its last user left in it (vectors keep their capacity):
//                  the new user assigns every field.
//
// Thread-safe: acquire and release from any threads (a slot is taken by compare-and-swap and given
// back with release ordering, so the next user sees everything the last one wrote).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

namespace gs::inline core {

class SlotSet {
public:
    explicit SlotSet(std::size_t capacity)
        : n_(capacity == 0 ? 1 : capacity), busy_(new std::atomic<bool>[n_]) {
        for (std::size_t i = 0; i < n_; ++i) busy_[i].store(false, std::memory_order_relaxed);
    }
    SlotSet(const SlotSet&) = delete;
    SlotSet& operator=(const SlotSet&) = delete;

    // A free slot, round robin (the one free the longest comes next), or nothing when every slot
    // is out (counted in exhausted()).
    std::optional<std::size_t> acquire() {
        const std::size_t start = next_.load(std::memory_order_relaxed);
        for (std::size_t k = 0; k < n_; ++k) {
            const std::size_t i = (start + k) % n_;
            bool expected = false;
            if (busy_[i].compare_exchange_strong(expected, true, std::memory_order_acquire)) {
                next_.store((i + 1) % n_, std::memory_order_relaxed);
                return i;
            }
        }
        exhausted_.fetch_add(1, std::memory_order_relaxed);
        return std::nullopt;
    }
    // Gives back a slot that acquire() returned.
    void release(std::size_t slot) { busy_[slot].store(false, std::memory_order_release); }

    std::size_t capacity() const { return n_; }
    std::size_t in_use() const {
        std::size_t n = 0;
        for (std::size_t i = 0; i < n_; ++i) n += busy_[i].load(std::memory_order_relaxed) ? 1 : 0;
        return n;
    }
    // How many acquire() calls found every slot out.
    std::uint64_t exhausted() const { return exhausted_.load(std::memory_order_relaxed); }

private:
    std::size_t n_;
    std::unique_ptr<std::atomic<bool>[]> busy_;
    std::atomic<std::size_t> next_{0};
    std::atomic<std::uint64_t> exhausted_{0};
};

template <class T>
class ObjectPool {
public:
    explicit ObjectPool(std::size_t capacity) : state_(new State(capacity)) {}
    ~ObjectPool() { state_->drop_holder(); }  // objects still out keep the pool's state alive
    ObjectPool(const ObjectPool&) = delete;
    ObjectPool& operator=(const ObjectPool&) = delete;

    // A free object, or nullptr when every one is out (counted in exhausted()). The object is
    // released back to the pool when the last copy of the returned pointer goes away. No
    // allocation: the pointer's bookkeeping (its control block) lives in the object's slot.
    std::shared_ptr<T> acquire() {
        const std::optional<std::size_t> slot = state_->slots.acquire();
        if (!slot) return nullptr;
        state_->holders.fetch_add(1, std::memory_order_relaxed);
        return std::shared_ptr<T>(&state_->objects[*slot], KeepObject{},
                                  SlotAllocator<T>(state_, *slot));
    }

    std::size_t capacity() const { return state_->slots.capacity(); }
    std::size_t in_use() const { return state_->slots.in_use(); }
    std::uint64_t exhausted() const { return state_->slots.exhausted(); }

private:
    // Room for a shared_ptr control block (a counted pointer with an empty deleter and this
    // allocator: about 40 bytes in libstdc++ and libc++; checked at compile time).
    struct alignas(std::max_align_t) Block {
        unsigned char bytes[96];
    };
    struct State {
        explicit State(std::size_t n)
            : slots(n), objects(new T[slots.capacity()]), blocks(new Block[slots.capacity()]) {}
        SlotSet slots;
        std::unique_ptr<T[]> objects;
        std::unique_ptr<Block[]> blocks;
        // The pool's handle plus one per object out: the last to go deletes the state.
        std::atomic<std::size_t> holders{1};
        void drop_holder() {
            if (holders.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
        }
    };
    // The object outlives its pointer: nothing to delete.
    struct KeepObject {
        void operator()(T*) const noexcept {}
    };
    // Places the control block in the slot's Block and, when the shared_ptr frees it (the last
    // copy gone, the block destroyed), releases the slot: the explicit release.
    template <class U>
    struct SlotAllocator {
        using value_type = U;
        State* state;
        std::size_t slot;
        SlotAllocator(State* s, std::size_t i) : state(s), slot(i) {}
        template <class V>
        SlotAllocator(const SlotAllocator<V>& o) : state(o.state), slot(o.slot) {}
        U* allocate(std::size_t n) {
            static_assert(sizeof(U) <= sizeof(Block) && alignof(U) <= alignof(Block),
                          "ObjectPool: a shared_ptr control block does not fit its slot");
            (void)n;  // always one control block
            return reinterpret_cast<U*>(state->blocks[slot].bytes);
        }
        void deallocate(U*, std::size_t) noexcept {
            state->slots.release(slot);
            state->drop_holder();  // may delete the state: nothing after it
        }
        template <class V>
        bool operator==(const SlotAllocator<V>& o) const {
            return state == o.state && slot == o.slot;
        }
    };
    State* state_;
};

}  // namespace gs::inline core
