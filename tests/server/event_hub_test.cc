#include "server/event_hub.h"

#include <thread>

#include <gtest/gtest.h>

namespace seamap::server {
namespace {

TEST(EventHub, ReturnsEventsAfterTheCursorInOrder) {
  EventHub hub;
  hub.Publish("tile", "{\"z\":1}");
  hub.Publish("pose", "{}");
  hub.Publish("track", "{}");
  auto events = hub.WaitAfter(1, std::chrono::milliseconds(0));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].id, 2u);
  EXPECT_EQ(events[0].type, "pose");
  EXPECT_EQ(events[1].id, 3u);
}

TEST(EventHub, KeepsABoundedHistory) {
  EventHub hub(3);
  for (int i = 0; i < 10; ++i) hub.Publish("tile", std::to_string(i));
  auto events = hub.WaitAfter(0, std::chrono::milliseconds(0));
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events.front().id, 8u);
  EXPECT_EQ(hub.LastId(), 10u);
}

TEST(EventHub, WakesAWaitingStreamWhenAnEventArrives) {
  EventHub hub;
  std::thread publisher([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    hub.Publish("progress", "{}");
  });
  auto events = hub.WaitAfter(0, std::chrono::seconds(30));
  publisher.join();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, "progress");
}

TEST(EventHub, CloseEndsWaitsWithNothing) {
  EventHub hub;
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    hub.Close();
  });
  auto events = hub.WaitAfter(0, std::chrono::seconds(30));
  closer.join();
  EXPECT_TRUE(events.empty());
  EXPECT_TRUE(hub.closed());
}

TEST(EventHub, CloseStillDeliversWhatIsLeft) {
  EventHub hub;
  hub.Publish("progress", "{\"state\":\"complete\"}");
  hub.Close();
  auto events = hub.WaitAfter(0, std::chrono::seconds(30));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].type, "progress");
  EXPECT_TRUE(hub.WaitAfter(1, std::chrono::seconds(30)).empty());  // at once, not after 30 s
}

TEST(EventHub, FormatsServerSentEvents) {
  EXPECT_EQ(FormatEvent({7, "tile", "{\"z\":3}"}), "id: 7\nevent: tile\ndata: {\"z\":3}\n\n");
}

}  // namespace
}  // namespace seamap::server
