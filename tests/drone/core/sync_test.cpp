#include "drone/core/sync.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace std::chrono_literals;

// ---- LatestValue ----------------------------------------------------------------------------

TEST(LatestValue, EmptyBeforeFirstPublish) {
    gs::LatestValue<int> v;
    EXPECT_FALSE(v.latest().has_value());
    EXPECT_EQ(v.generation(), 0u);
    std::uint64_t seen = 0;
    int out = -1;
    EXPECT_FALSE(v.read_if_newer(seen, out));
    EXPECT_EQ(out, -1);
}

TEST(LatestValue, ReaderCopiesOnlyWhenGenerationMoved) {
    gs::LatestValue<std::string> v;
    std::uint64_t seen = 0;
    std::string out;
    v.publish("a");
    ASSERT_TRUE(v.read_if_newer(seen, out));
    EXPECT_EQ(out, "a");
    EXPECT_EQ(seen, 1u);
    out = "untouched";
    EXPECT_FALSE(v.read_if_newer(seen, out));
    EXPECT_EQ(out, "untouched");
    v.publish("b");
    v.publish("c");  // reader only ever sees the newest: "b" is skipped, not queued
    ASSERT_TRUE(v.read_if_newer(seen, out));
    EXPECT_EQ(out, "c");
    EXPECT_EQ(seen, 3u);
    EXPECT_EQ(*v.latest(), "c");
}

TEST(LatestValue, IndependentReadersTrackTheirOwnGeneration) {
    gs::LatestValue<int> v;
    std::uint64_t a = 0, b = 0;
    int out = 0;
    v.publish(1);
    EXPECT_TRUE(v.read_if_newer(a, out));
    v.publish(2);
    EXPECT_TRUE(v.read_if_newer(b, out));
    EXPECT_EQ(out, 2);
    EXPECT_TRUE(v.read_if_newer(a, out));
    EXPECT_FALSE(v.read_if_newer(b, out));
}

TEST(LatestValue, ConcurrentReadersNeverSeeTornValues) {
    // The value is a pair that is always published consistent (second == 2 * first).
    gs::LatestValue<std::pair<std::uint64_t, std::uint64_t>> v;
    std::atomic<bool> done{false};
    std::atomic<std::uint64_t> bad{0}, reads{0};
    std::thread reader([&] {
        std::uint64_t seen = 0, last_first = 0;
        std::pair<std::uint64_t, std::uint64_t> out;
        while (!done.load()) {
            if (v.read_if_newer(seen, out)) {
                if (out.second != 2 * out.first || out.first < last_first) ++bad;
                last_first = out.first;
                ++reads;
            }
        }
    });
    for (std::uint64_t i = 1; i <= 50000; ++i) v.publish({i, 2 * i});
    done = true;
    reader.join();
    EXPECT_EQ(bad.load(), 0u);
    EXPECT_EQ(v.generation(), 50000u);
    EXPECT_EQ(v.latest()->first, 50000u);
}

// ---- BoundedQueue: policies -----------------------------------------------------------------

TEST(BoundedQueue, RejectNewKeepsOldestAndCountsDrops) {
    gs::BoundedQueue<int> q(3, gs::QueueFull::RejectNew);
    int accepted = 0;
    for (int i = 1; i <= 5; ++i) accepted += q.push(i) ? 1 : 0;
    EXPECT_EQ(accepted, 3);
    EXPECT_EQ(q.dropped(), 2u);
    EXPECT_EQ(q.size(), 3u);
    EXPECT_EQ(q.high_water(), 3u);
    EXPECT_EQ(q.try_pop(), 1);
    EXPECT_EQ(q.try_pop(), 2);
    EXPECT_EQ(q.try_pop(), 3);
    EXPECT_FALSE(q.try_pop().has_value());
}

TEST(BoundedQueue, DropOldestKeepsNewestAndCountsDrops) {
    gs::BoundedQueue<int> q(3, gs::QueueFull::DropOldest);
    for (int i = 1; i <= 5; ++i) EXPECT_TRUE(q.push(i));
    EXPECT_EQ(q.dropped(), 2u);
    EXPECT_EQ(q.size(), 3u);
    EXPECT_EQ(q.try_pop(), 3);
    EXPECT_EQ(q.try_pop(), 4);
    EXPECT_EQ(q.try_pop(), 5);
    EXPECT_FALSE(q.try_pop().has_value());
}

TEST(BoundedQueue, ZeroCapacityMeansOne) {
    gs::BoundedQueue<int> q(0);
    EXPECT_EQ(q.capacity(), 1u);
    EXPECT_TRUE(q.push(1));
    EXPECT_FALSE(q.push(2));
    EXPECT_EQ(q.dropped(), 1u);
}

TEST(BoundedQueue, MoveOnlyItems) {
    gs::BoundedQueue<std::unique_ptr<int>> q(2);
    EXPECT_TRUE(q.push(std::make_unique<int>(7)));
    auto v = q.try_pop();
    ASSERT_TRUE(v && *v);
    EXPECT_EQ(**v, 7);
}

// ---- BoundedQueue: close and waiting --------------------------------------------------------

TEST(BoundedQueue, PushAfterCloseIsRejectedAndCounted) {
    gs::BoundedQueue<int> q(4, gs::QueueFull::DropOldest);
    ASSERT_TRUE(q.push(1));
    q.close();
    EXPECT_TRUE(q.closed());
    EXPECT_FALSE(q.push(2));
    EXPECT_EQ(q.dropped(), 1u);
    // Items queued before the close are still delivered, then pop reports the end.
    EXPECT_EQ(q.pop_for(0ms), 1);
    EXPECT_FALSE(q.pop_for(0ms).has_value());
}

TEST(BoundedQueue, PopForTimesOutOnEmptyQueue) {
    gs::BoundedQueue<int> q(4);
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(q.pop_for(20ms).has_value());
    EXPECT_GE(std::chrono::steady_clock::now() - t0, 20ms);
}

TEST(BoundedQueue, CloseWakesAWaitingPop) {
    gs::BoundedQueue<int> q(4);
    std::optional<int> got = 99;
    std::chrono::steady_clock::duration waited{};
    std::thread consumer([&] {
        const auto t0 = std::chrono::steady_clock::now();
        got = q.pop_for(30s);
        waited = std::chrono::steady_clock::now() - t0;
    });
    q.close();  // whether the consumer is already waiting or not, it must return nullopt
    consumer.join();
    EXPECT_FALSE(got.has_value());
    EXPECT_LT(waited, 10s);  // woken, not timed out
}

TEST(BoundedQueue, PushWakesAWaitingPop) {
    gs::BoundedQueue<int> q(4);
    std::optional<int> got;
    std::thread consumer([&] { got = q.pop_for(30s); });
    EXPECT_TRUE(q.push(42));
    consumer.join();
    EXPECT_EQ(got, 42);
}

// ---- BoundedQueue: many threads -------------------------------------------------------------

namespace {

struct Item {
    int producer;
    int index;
};

// Runs `producers` threads pushing `per_producer` items each and `consumers` threads popping until
// the queue is closed and drained. Returns what each consumer received, in order.
std::vector<std::vector<Item>> run_mpmc(gs::BoundedQueue<Item>& q, int producers, int per_producer,
                                        int consumers, bool retry_when_full,
                                        std::atomic<std::uint64_t>& accepted) {
    std::vector<std::vector<Item>> got(static_cast<std::size_t>(consumers));
    std::vector<std::thread> cons;
    for (int c = 0; c < consumers; ++c) {
        cons.emplace_back([&q, &out = got[static_cast<std::size_t>(c)]] {
            while (true) {
                auto v = q.pop_for(100ms);
                if (v) {
                    out.push_back(*v);
                } else if (q.closed() && q.size() == 0) {
                    return;
                }
            }
        });
    }
    std::vector<std::thread> prods;
    for (int p = 0; p < producers; ++p) {
        prods.emplace_back([&, p] {
            for (int i = 0; i < per_producer; ++i) {
                while (!q.push(Item{p, i})) {
                    if (!retry_when_full) break;
                    std::this_thread::yield();
                }
                if (retry_when_full) ++accepted;
            }
        });
    }
    for (auto& t : prods) t.join();
    q.close();
    for (auto& t : cons) t.join();
    return got;
}

}  // namespace

TEST(BoundedQueueThreads, ProducersAndConsumersPreserveOrderAndCount) {
    constexpr int kProducers = 3, kPerProducer = 5000, kConsumers = 2;
    gs::BoundedQueue<Item> q(64, gs::QueueFull::RejectNew);
    std::atomic<std::uint64_t> accepted{0};
    auto got =
        run_mpmc(q, kProducers, kPerProducer, kConsumers, /*retry_when_full=*/true, accepted);
    std::vector<std::vector<bool>> seen(kProducers, std::vector<bool>(kPerProducer, false));
    std::size_t total = 0;
    for (const auto& consumer : got) {
        std::vector<int> last(kProducers, -1);
        for (const Item& it : consumer) {
            // FIFO: each consumer sees every producer's items in increasing order.
            ASSERT_GT(it.index, last[static_cast<std::size_t>(it.producer)]);
            last[static_cast<std::size_t>(it.producer)] = it.index;
            auto&& slot =
                seen[static_cast<std::size_t>(it.producer)][static_cast<std::size_t>(it.index)];
            ASSERT_FALSE(slot) << "duplicate item";
            slot = true;
            ++total;
        }
    }
    EXPECT_EQ(total, std::size_t{kProducers} * kPerProducer);  // nothing lost
    EXPECT_EQ(accepted.load(), std::uint64_t{kProducers} * kPerProducer);
    EXPECT_LE(q.high_water(), 64u);
}

TEST(BoundedQueueThreads, SingleConsumerSeesGlobalFifoOrder) {
    gs::BoundedQueue<Item> q(16, gs::QueueFull::RejectNew);
    std::atomic<std::uint64_t> accepted{0};
    auto got = run_mpmc(q, 1, 10000, 1, true, accepted);
    ASSERT_EQ(got[0].size(), 10000u);
    for (int i = 0; i < 10000; ++i) ASSERT_EQ(got[0][static_cast<std::size_t>(i)].index, i);
}

TEST(BoundedQueueThreads, DropOldestAccountsForEveryItem) {
    constexpr int kProducers = 4, kPerProducer = 20000;
    gs::BoundedQueue<Item> q(8, gs::QueueFull::DropOldest);
    std::atomic<std::uint64_t> unused{0};
    auto got = run_mpmc(q, kProducers, kPerProducer, 1, /*retry_when_full=*/false, unused);
    std::vector<int> last(kProducers, -1);
    for (const Item& it : got[0]) {
        ASSERT_GT(it.index, last[static_cast<std::size_t>(it.producer)]);  // order survives drops
        last[static_cast<std::size_t>(it.producer)] = it.index;
    }
    // Every pushed item was either delivered or counted as dropped.
    EXPECT_EQ(got[0].size() + q.dropped(), std::uint64_t{kProducers} * kPerProducer);
}
