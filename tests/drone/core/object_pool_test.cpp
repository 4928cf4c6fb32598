#include "drone/core/object_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <vector>

// ---- SlotSet ---------------------------------------------------------------------------------

TEST(ObjectPool, SlotSetHandsOutEachSlotOnceThenCountsExhaustion) {
    gs::SlotSet s(3);
    std::set<std::size_t> taken;
    for (int i = 0; i < 3; ++i) {
        const std::optional<std::size_t> k = s.acquire();
        ASSERT_TRUE(k);
        EXPECT_LT(*k, 3u);
        taken.insert(*k);
    }
    EXPECT_EQ(taken.size(), 3u);
    EXPECT_EQ(s.in_use(), 3u);
    EXPECT_FALSE(s.acquire());
    EXPECT_FALSE(s.acquire());
    EXPECT_EQ(s.exhausted(), 2u);
    s.release(1);
    EXPECT_EQ(s.in_use(), 2u);
    EXPECT_EQ(s.acquire(), std::optional<std::size_t>(1));
    EXPECT_EQ(s.exhausted(), 2u);
}

TEST(ObjectPool, SlotSetGoesRoundRobin) {
    gs::SlotSet s(3);
    const auto a = s.acquire();
    ASSERT_TRUE(a);
    s.release(*a);
    const auto b = s.acquire();  // not the slot just given back: the one free the longest
    ASSERT_TRUE(b);
    EXPECT_NE(*a, *b);
}

TEST(ObjectPool, SlotSetOfZeroHasOneSlot) {
    gs::SlotSet s(0);
    EXPECT_EQ(s.capacity(), 1u);
    EXPECT_TRUE(s.acquire());
    EXPECT_FALSE(s.acquire());
}

// ---- ObjectPool ------------------------------------------------------------------------------

TEST(ObjectPool, AcquiresUpToCapacityThenReturnsNothingCounted) {
    gs::ObjectPool<int> pool(2);
    auto a = pool.acquire(), b = pool.acquire();
    ASSERT_TRUE(a && b);
    EXPECT_NE(a.get(), b.get());
    EXPECT_EQ(pool.in_use(), 2u);
    EXPECT_EQ(pool.acquire(), nullptr);
    EXPECT_EQ(pool.exhausted(), 1u);
}

TEST(ObjectPool, ReleasedWhenTheLastCopyGoesAndReusedWithItsContents) {
    gs::ObjectPool<std::vector<int>> pool(1);
    auto a = pool.acquire();
    ASSERT_TRUE(a);
    a->assign(100, 7);
    std::vector<int>* const where = a.get();
    auto copy = a;
    a.reset();
    EXPECT_EQ(pool.in_use(), 1u);  // a copy still holds it
    EXPECT_EQ(pool.acquire(), nullptr);
    copy.reset();
    EXPECT_EQ(pool.in_use(), 0u);
    auto again = pool.acquire();
    ASSERT_TRUE(again);
    EXPECT_EQ(again.get(), where);
    EXPECT_EQ(again->size(), 100u);  // what the last user left: the new one assigns every field
    EXPECT_GE(again->capacity(), 100u);
}

TEST(ObjectPool, AnObjectOutlivesItsPool) {
    std::shared_ptr<std::vector<int>> kept;
    {
        gs::ObjectPool<std::vector<int>> pool(2);
        kept = pool.acquire();
        ASSERT_TRUE(kept);
    }
    kept->assign(1000, 3);  // still valid (AddressSanitizer checks this)
    EXPECT_EQ(kept->at(999), 3);
    kept.reset();
}

TEST(ObjectPool, ConvertsToAPointerToConst) {
    gs::ObjectPool<int> pool(1);
    std::shared_ptr<const int> c = pool.acquire();
    ASSERT_TRUE(c);
    EXPECT_EQ(pool.in_use(), 1u);
    c.reset();
    EXPECT_EQ(pool.in_use(), 0u);
}

// Acquired on one thread, released on others (the session's outputs): no object is ever held by
// two users at once, and every acquire is either served or counted.
TEST(ObjectPool, AcquireOnOneThreadReleaseOnOthers) {
    struct Item {
        std::atomic<int> users{0};
        std::uint64_t value = 0;
    };
    gs::ObjectPool<Item> pool(4);
    constexpr int kItems = 20000;
    std::vector<std::shared_ptr<Item>> handoff[2];
    std::atomic<bool> overlap{false};
    std::atomic<int> served{0};
    std::atomic<bool> done{false};
    std::mutex m[2];
    std::vector<std::thread> readers;
    for (int r = 0; r < 2; ++r)
        readers.emplace_back([&, r] {
            for (;;) {
                std::vector<std::shared_ptr<Item>> got;
                {
                    std::lock_guard lk(m[r]);
                    got.swap(handoff[r]);
                }
                for (auto& it : got) {
                    if (it->value == 0) overlap = true;
                    it->value = 0;
                    if (it->users.fetch_sub(1) != 1) overlap = true;
                }
                got.clear();  // released here, on this thread
                if (done) {
                    std::lock_guard lk(m[r]);
                    if (handoff[r].empty()) return;
                }
                std::this_thread::yield();
            }
        });
    int attempts = 0;
    for (int i = 0; i < kItems; ++i) {
        ++attempts;
        auto it = pool.acquire();
        if (!it) continue;
        if (it->users.fetch_add(1) != 0) overlap = true;
        it->value = static_cast<std::uint64_t>(i) + 1;
        ++served;
        std::lock_guard lk(m[i % 2]);
        handoff[i % 2].push_back(std::move(it));
    }
    done = true;
    for (auto& t : readers) t.join();
    EXPECT_FALSE(overlap);
    EXPECT_EQ(static_cast<std::uint64_t>(served) + pool.exhausted(),
              static_cast<std::uint64_t>(attempts));
    EXPECT_GT(served, 0);
    EXPECT_EQ(pool.in_use(), 0u);
}
