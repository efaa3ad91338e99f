#include "owval/trajectory/track_choice.hpp"

#include <gtest/gtest.h>

#include "owval/base/errors.hpp"

namespace owval {
namespace {

TEST(TrackChoice, NothingGivenKeepsTheBaseTrack) {
  const Track base{4, "liquid", Axis::kZ};
  const Track t = TrackChoice{}.Over(base);
  EXPECT_FALSE(TrackChoice{}.given());
  EXPECT_EQ(t.particle, 4u);
  EXPECT_EQ(t.group, "liquid");
  EXPECT_EQ(t.axis, Axis::kZ);
}

TEST(TrackChoice, AParticleReplacesTheBasesGroupAndKeepsItsAxis) {
  TrackChoice choice;
  choice.particle = 7;
  const Track t = choice.Over(Track{0, "elastic", Axis::kX});
  EXPECT_TRUE(choice.given());
  EXPECT_EQ(t.particle, 7u);
  EXPECT_EQ(t.group, "");
  EXPECT_EQ(t.axis, Axis::kX);
}

TEST(TrackChoice, AGroupAndAnAxisAreLaidOverTheBase) {
  TrackChoice choice;
  choice.group = "all";
  choice.axis = "z";
  const Track t = choice.Over(Track{});
  EXPECT_EQ(t.group, "all");
  EXPECT_EQ(t.axis, Axis::kZ);
}

TEST(TrackChoice, AnUnknownAxisIsBadInput) {
  TrackChoice choice;
  choice.axis = "w";
  EXPECT_THROW(choice.Over(Track{}), InputError);
}

}  // namespace
}  // namespace owval
