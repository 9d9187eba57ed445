// Tests coordinator/status/connection_shedder.cpp: under the caps nothing is shed; past the total the oldest of
// all goes, past an address's cap the oldest of that address; a shed connection counts no more and its late close
// changes nothing; a crowd of any size leaves the listener at its caps with the newest connections in.

#include "coordinator/status/connection_shedder.h"

#include <gtest/gtest.h>

#include <string>

namespace poet {
namespace {

TEST(ConnectionShedderTest, UnderTheCapsNothingIsShed) {
  ConnectionShedder shedder({.total = 4, .per_address = 2});
  EXPECT_FALSE(shedder.open("a").shed);
  EXPECT_FALSE(shedder.open("a").shed);
  EXPECT_FALSE(shedder.open("b").shed);
  const ConnectionShedder::Admission last = shedder.open("c");
  EXPECT_FALSE(last.shed);
  EXPECT_EQ(last.id, 4u);
  EXPECT_EQ(shedder.size(), 4u);
  EXPECT_EQ(shedder.count("a"), 2u);
  EXPECT_EQ(shedder.count("z"), 0u);
}

TEST(ConnectionShedderTest, PastTheTotalTheOldestGoes) {
  ConnectionShedder shedder({.total = 3, .per_address = 3});
  const auto first = shedder.open("a").id;
  const auto second = shedder.open("b").id;
  shedder.open("c");
  const ConnectionShedder::Admission fourth = shedder.open("d");
  EXPECT_EQ(fourth.shed, first);
  EXPECT_EQ(shedder.size(), 3u);
  EXPECT_EQ(shedder.count("a"), 0u);
  // the shed one's close, when the server gets to it, changes nothing
  shedder.close(first);
  EXPECT_EQ(shedder.size(), 3u);
  EXPECT_EQ(shedder.open("e").shed, second);
}

TEST(ConnectionShedderTest, PastAnAddressCapItsOwnOldestGoes) {
  ConnectionShedder shedder({.total = 10, .per_address = 2});
  const auto elsewhere = shedder.open("b").id;  // the oldest of all, from another address
  const auto oldest = shedder.open("a").id;
  shedder.open("a");
  EXPECT_EQ(shedder.open("a").shed, oldest);
  EXPECT_EQ(shedder.count("a"), 2u);
  EXPECT_EQ(shedder.count("b"), 1u) << "connection " << elsewhere << " stays";
}

TEST(ConnectionShedderTest, ClosedConnectionsMakeRoom) {
  ConnectionShedder shedder({.total = 2, .per_address = 2});
  const auto first = shedder.open("a").id;
  shedder.open("a");
  shedder.close(first);
  shedder.close(first);  // twice: ignored
  shedder.close(12345);  // never opened: ignored
  EXPECT_EQ(shedder.size(), 1u);
  EXPECT_FALSE(shedder.open("a").shed);
}

TEST(ConnectionShedderTest, ACrowdKeepsTheListenerAtItsCapsAndTheNewestIn) {
  ConnectionShedder shedder({.total = 100, .per_address = 30});
  int shed = 0;
  for (int i = 0; i < 1100; ++i) shed += shedder.open("10.0.0." + std::to_string(i % 5)).shed.has_value();
  EXPECT_EQ(shedder.size(), 100u);
  EXPECT_EQ(shed, 1000);
  for (int a = 0; a < 5; ++a) EXPECT_LE(shedder.count("10.0.0." + std::to_string(a)), 30u);
  // a probe from an address of its own gets in, and so does one from the crowd's
  const ConnectionShedder::Admission probe = shedder.open("127.0.0.1");
  EXPECT_TRUE(probe.shed);
  EXPECT_EQ(shedder.count("127.0.0.1"), 1u);
  EXPECT_TRUE(shedder.open("10.0.0.0").shed);
  EXPECT_EQ(shedder.count("127.0.0.1"), 1u) << "the probe is not the oldest";
}

TEST(ConnectionShedderTest, CapsAreKeptInRange) {
  ConnectionShedder shedder({.total = 0, .per_address = 0});  // read as 1 and 1
  EXPECT_FALSE(shedder.open("a").shed);
  EXPECT_TRUE(shedder.open("b").shed);
  EXPECT_EQ(shedder.size(), 1u);
}

}  // namespace
}  // namespace poet
