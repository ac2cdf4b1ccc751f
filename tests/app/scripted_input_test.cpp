// Scripted window input (run --input): each event's text read into the key, wheel, drag or click the window's handlers take, and every malformed one refused with one line naming it.
#include "app/scripted_input.h"

#include <gtest/gtest.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

namespace dentsim::app {
namespace {

TEST(ScriptedInput, KeysWheelsDragsAndClicksReadAsTheWindowWouldSeeThem) {
  auto b = parseScriptedInput(0.5, "key:B");
  ASSERT_TRUE(b.ok()) << b.message();
  EXPECT_EQ(b->kind, ScriptedInput::Kind::Key);
  EXPECT_EQ(b->key, GLFW_KEY_B);
  EXPECT_EQ(b->mods, 0);
  EXPECT_DOUBLE_EQ(b->t_s, 0.5);
  auto up = parseScriptedInput(0, "shift+key:Up");
  ASSERT_TRUE(up.ok());
  EXPECT_EQ(up->key, GLFW_KEY_UP);
  EXPECT_EQ(up->mods, GLFW_MOD_SHIFT);
  EXPECT_EQ(parseScriptedInput(0, "key:s")->key, GLFW_KEY_S);
  EXPECT_EQ(parseScriptedInput(0, "key:1")->key, GLFW_KEY_1);
  EXPECT_EQ(parseScriptedInput(0, "key:F1")->key, GLFW_KEY_F1);
  auto wheel = parseScriptedInput(1, "ctrl+wheel:-2.5");
  ASSERT_TRUE(wheel.ok());
  EXPECT_EQ(wheel->kind, ScriptedInput::Kind::Wheel);
  EXPECT_EQ(wheel->mods, GLFW_MOD_CONTROL);
  EXPECT_DOUBLE_EQ(wheel->dy, -2.5);
  auto drag = parseScriptedInput(1, "drag:12,-30");
  ASSERT_TRUE(drag.ok());
  EXPECT_EQ(drag->kind, ScriptedInput::Kind::Drag);
  EXPECT_DOUBLE_EQ(drag->dx, 12);
  EXPECT_DOUBLE_EQ(drag->dy, -30);
  auto click = parseScriptedInput(2, "click:score");
  ASSERT_TRUE(click.ok());
  EXPECT_EQ(click->kind, ScriptedInput::Kind::Click);
  EXPECT_EQ(click->widget, "score");
}

TEST(ScriptedInput, MalformedEventsAreOneLineErrorsNamingThem) {
  for (const char* bad : {"", "key", "key:", "key:Foo", "key:%s%n", "wheel:x", "wheel:1e9", "wheel:nan", "drag:1",
                          "drag:1,", "drag:a,b", "click:", "shift+click:score", "tap:B", "alt+"}) {
    auto r = parseScriptedInput(0, bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find("--input \"" + std::string(bad) + "\""), std::string::npos) << r.message();
    EXPECT_EQ(r.message().find('\n'), std::string::npos) << r.message();
  }
  EXPECT_FALSE(parseScriptedInput(-1, "key:B").ok());
}

TEST(ScriptedInput, EventsAreSortedByTimeKeepingTheOrderGivenWithinATime) {
  auto all = parseScriptedInputs({{2.0, "key:S"}, {0.5, "key:B"}, {2.0, "key:Space"}, {1.0, "wheel:-1"}});
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 4u);
  EXPECT_EQ((*all)[0].text, "key:B");
  EXPECT_EQ((*all)[1].text, "wheel:-1");
  EXPECT_EQ((*all)[2].text, "key:S");
  EXPECT_EQ((*all)[3].text, "key:Space");
  EXPECT_FALSE(parseScriptedInputs({{0.0, "key:B"}, {1.0, "nope"}}).ok());
}

}  // namespace
}  // namespace dentsim::app
