// The device handler: pen and pedal names, software pens behind the interface, and the listing.
#include "devices/device_registry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "devices/software_pen.h"
#include "devices/virtual_pen.h"
#include "io/pen_path_file.h"
#include "io/pen_playback.h"
#include "test_support.h"

namespace dentsim::devices {
namespace {

TEST(PenNames, ParseEveryBackendAndItsDefaults) {
  auto v = parsePenName("virtual");
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(v->backend, "virtual");
  EXPECT_TRUE(v->software());
  auto f = parsePenName("falcon");
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->arg, "0");
  EXPECT_FALSE(f->software());
  EXPECT_EQ(parsePenName("falcon:3")->arg, "3");
  EXPECT_EQ(parsePenName("openhaptics")->arg, "Default");
  EXPECT_EQ(parsePenName("openhaptics:Left Touch")->arg, "Left Touch");
  EXPECT_EQ(parsePenName("script:a:b.csv")->arg, "a:b.csv");  // only the first colon separates
  EXPECT_EQ(parsePenName("replay:s.dses")->backend, "replay");
}

TEST(PenNames, BadNamesSayWhatAndWhy) {
  for (const char* bad : {"", "falconx", "falcon:-1", "falcon:-0", "falcon:+1", "falcon:1x", "falcon:64", "virtual:2", "script:",
                          "replay", "mouse"}) {
    auto r = parsePenName(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find(std::string("'") + bad + "'"), std::string::npos) << r.message();
  }
  auto r = parsePenName("mouse");
  EXPECT_NE(r.message().find("falcon"), std::string::npos) << "the error lists the choices: " << r.message();
  // A line break typed into a name is echoed escaped: the error stays one line.
  auto broken = parsePenName("falcon:\n");
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.message().find('\n'), std::string::npos) << broken.message();
  EXPECT_NE(broken.message().find("pen 'falcon:\\x0a'"), std::string::npos) << broken.message();
}

TEST(SoftwarePens, AScriptBehindTheInterfaceReadsLikeTheScriptedPen) {
  dentsim::test::TempDir dir;
  PenPath path;
  for (int k = 0; k <= 10; ++k) {
    PenSample s;
    s.t_s = 0.01 * k;
    s.pen = PenRole::Drill;
    s.pose.position = {double(k), 0, 0};
    s.pedal = 0.1 * k;
    path.samples.push_back(s);
  }
  ASSERT_TRUE(savePenPath(dir.file("p.csv"), path).ok());
  PenContext context;
  context.max_force_n = 4.0;
  auto pen = makePen(*parsePenName("script:" + dir.file("p.csv")), context);
  ASSERT_TRUE(pen.ok()) << pen.message();
  HapticDevice& d = **pen;
  EXPECT_FALSE(d.spec().physical);
  EXPECT_EQ(d.spec().max_force_n, 4.0);
  ASSERT_TRUE(d.open().ok());
  ASSERT_TRUE(d.enable().ok());
  ScriptedPen direct(path, PenRole::Drill);
  for (double t : {0.0, 0.015, 0.05, 0.2}) {
    DeviceReading r;
    PenReading want;
    d.command(Wrench{}, std::llround(t * 1e9));  // as the loop does each step: no watchdog
    ASSERT_TRUE(d.read(t, &r));
    ASSERT_TRUE(direct.read(t, &want));
    EXPECT_EQ(r.pose, want.grip) << t;
    EXPECT_EQ(r.velocity, want.velocity) << t;
    EXPECT_TRUE(r.has_pedal);
    EXPECT_EQ(r.pedal, want.pedal) << t;
  }
  // The safety layer runs on loop time: a small command arms it, then 9 N comes out clamped to 4 N.
  auto& sw = static_cast<SoftwarePen&>(d);
  d.command(Wrench{{0, 0, 0.1}, {}}, 210'000'000);
  DeviceReading r;
  ASSERT_TRUE(d.read(0.211, &r));
  EXPECT_EQ(sw.lastOutput().gate, SafetyGate::Pass);
  d.command(Wrench{{0, 9, 0}, {}}, 1'000'000'000);
  ASSERT_TRUE(d.read(1.0005, &r));
  EXPECT_NEAR(sw.lastOutput().wrench.force.y, 4.0, 1e-12);
  // The pen script's own record of what it was shown is what the motors would have got.
  EXPECT_NEAR(static_cast<ScriptedPen&>(sw.source()).lastDisplayed().force.y, 4.0, 1e-12);
}

TEST(SoftwarePens, MissingFilesAndAbsentPensAreOneLineErrors) {
  dentsim::test::TempDir dir;
  auto missing = makePen(*parsePenName("script:" + dir.file("none.csv")), {});
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("none.csv"), std::string::npos) << missing.message();
  EXPECT_EQ(missing.message().find('\n'), std::string::npos);
  auto no_session = makePen(*parsePenName("replay:" + dir.file("none.dses")), {});
  ASSERT_FALSE(no_session.ok());
  EXPECT_NE(no_session.message().find("none.dses"), std::string::npos) << no_session.message();
  PenPath drill_only;
  PenSample s;
  drill_only.samples.push_back(s);
  ASSERT_TRUE(savePenPath(dir.file("d.csv"), drill_only).ok());
  PenContext mirror;
  mirror.role = PenRole::Mirror;
  auto none = makePen(*parsePenName("script:" + dir.file("d.csv")), mirror);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("mirror"), std::string::npos) << none.message();
}

TEST(SoftwarePens, TheVirtualPenStartsWhereItIsPut) {
  PenContext context;
  context.start_grip.position = {1, 2, 3};
  auto pen = makePen(*parsePenName("virtual"), context);
  ASSERT_TRUE(pen.ok());
  ASSERT_TRUE((*pen)->open().ok());
  EXPECT_EQ((*pen)->state(), DeviceState::Ready);
  DeviceReading r;
  ASSERT_TRUE((*pen)->read(0.0, &r));
  EXPECT_EQ(r.pose.position, (Vec3{1, 2, 3}));
  auto& source = static_cast<SoftwarePen&>(**pen).source();
  EXPECT_NE(dynamic_cast<VirtualPen*>(&source), nullptr);
  (*pen)->close();
  EXPECT_EQ((*pen)->state(), DeviceState::Disconnected);
  EXPECT_FALSE((*pen)->read(0.001, &r));
}

TEST(Pedals, NamesAreCheckedAndNoneIsNoPedal) {
  auto none = makePedal("none");
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none->get(), nullptr);
  auto bad = makePedal("usbpedal");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("'usbpedal'"), std::string::npos) << bad.message();
}

TEST(DeviceList, TheVirtualPenIsAlwaysFirstAndReady) {
  const std::vector<DeviceEntry> all = listDevices();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front().name, "virtual");
  EXPECT_EQ(all.front().state, DeviceState::Ready);
  for (const DeviceEntry& e : all) {
    EXPECT_FALSE(e.name.empty());
    EXPECT_TRUE(e.kind == "pen" || e.kind == "pedal") << e.name;
    // Anything not usable says why.
    if (e.state != DeviceState::Ready && e.state != DeviceState::Enabled) {
      EXPECT_FALSE(e.reason.empty()) << e.name;
    }
  }
}

}  // namespace
}  // namespace dentsim::devices
