// The pilot's stick input to flight commands (app/pilot_commands.hpp): a Move when what is sent
// changes, nothing while it holds, one Hover on release, nothing after.

#include "app/pilot_commands.hpp"

#include <gtest/gtest.h>

#include <variant>

namespace gs::app {
namespace {

TEST(PilotCommands, MovesOnChangeAndHoversOnceOnRelease) {
    PilotCommands p;
    EXPECT_FALSE(p.next(std::nullopt));  // never steered: nothing to release

    const link::Move fwd{0, -0.5f, 0, 0};
    auto c = p.next(fwd);
    ASSERT_TRUE(c);
    ASSERT_TRUE(std::holds_alternative<link::Move>(*c));
    EXPECT_FLOAT_EQ(std::get<link::Move>(*c).pitch, -0.5f);
    EXPECT_FALSE(p.next(fwd));  // held: the link repeats it, nothing new to send

    const link::Move turn{0, -0.5f, 0, 0.25f};
    c = p.next(turn);
    ASSERT_TRUE(c);
    EXPECT_FLOAT_EQ(std::get<link::Move>(*c).yaw, 0.25f);
    EXPECT_EQ(p.moves(), 2u);

    c = p.next(std::nullopt);
    ASSERT_TRUE(c);
    EXPECT_TRUE(std::holds_alternative<link::Hover>(*c));
    EXPECT_FALSE(p.next(std::nullopt));
    EXPECT_EQ(p.hovers(), 1u);

    // After a reset (a new source) the same input is sent again.
    EXPECT_TRUE(p.next(fwd));
    p.reset();
    EXPECT_FALSE(p.next(std::nullopt));  // the new source was never steered
    EXPECT_TRUE(p.next(fwd));
    EXPECT_EQ(p.moves(), 4u);
}

}  // namespace
}  // namespace gs::app
