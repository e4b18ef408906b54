// BoundedQueue: the drop policy between stages, waiting for room (sources that can wait) and
// shutdown releasing every waiter.
#include "server/pipeline/bounded_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace omnisweep::pipeline {
namespace {

TEST(BoundedQueue, FullQueueDropsTheOldestAndSaysSo) {
  BoundedQueue<int> queue(2);
  EXPECT_FALSE(queue.push(1));
  EXPECT_FALSE(queue.push(2));
  EXPECT_TRUE(queue.push(3));  // 1 is dropped
  EXPECT_EQ(queue.pop(), 2);
  EXPECT_EQ(queue.pop(), 3);
}

TEST(BoundedQueue, WaitForRoomBlocksUntilTheConsumerTakesAnItem) {
  BoundedQueue<int> queue(1);
  queue.push(1);
  std::atomic<bool> returned{false};
  std::thread producer([&] {
    EXPECT_TRUE(queue.wait_for_room());
    returned = true;
    EXPECT_FALSE(queue.push(2));  // room: nothing dropped
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(returned) << "wait_for_room returned while the queue was full";
  EXPECT_EQ(queue.pop(), 1);
  producer.join();
  EXPECT_TRUE(returned);
  EXPECT_EQ(queue.pop(), 2);
  EXPECT_TRUE(queue.wait_for_room());  // empty: at once
}

TEST(BoundedQueue, CloseReleasesProducersAndConsumers) {
  BoundedQueue<int> full(1), empty(1);
  full.push(1);
  std::thread producer([&] { EXPECT_FALSE(full.wait_for_room()); });
  std::thread consumer([&] { EXPECT_EQ(empty.pop(), std::nullopt); });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  full.close();
  empty.close();
  producer.join();
  consumer.join();
  EXPECT_FALSE(full.push(2)) << "a closed queue takes nothing";
  EXPECT_EQ(full.pop(), std::nullopt);
}

}  // namespace
}  // namespace omnisweep::pipeline
