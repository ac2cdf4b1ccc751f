// SoundFeed: removal rates and tissue shares from the loop's running totals, counted by hand.
#include "audio/sound_feed.h"

#include <gtest/gtest.h>

namespace dentsim::audio {
namespace {

HapticState stateAt(double t_s, double enamel_mm3, double dentin_mm3, double rpm = 20000.0) {
  HapticState s;
  s.t_s = t_s;
  s.rpm = rpm;
  s.removed_by_material_mm3[DS_MAT_ENAMEL] = enamel_mm3;
  s.removed_by_material_mm3[DS_MAT_DENTIN] = dentin_mm3;
  s.removed_mm3 = enamel_mm3 + dentin_mm3;
  return s;
}

TEST(SoundFeed, RatesAndSharesAreOverTheTimeSinceTheLastCall) {
  SoundFeed feed;
  // From loop time 0: 0.02 mm^3 of enamel in 0.1 s.
  SoundInput in = feed.next(stateAt(0.1, 0.02, 0.0), {1, 2, 3});
  EXPECT_DOUBLE_EQ(in.removal_mm3_per_s, 0.2);
  EXPECT_EQ(in.removal_share[tissueIndex(Material::Enamel)], 1.0);
  EXPECT_EQ(in.handpiece_mm, (Vec3{1, 2, 3}));
  EXPECT_EQ(in.turbine_rpm, 20000.0);
  // Then 0.01 more enamel and 0.03 dentin in 0.05 s: 0.8 mm^3/s, a quarter enamel.
  in = feed.next(stateAt(0.15, 0.03, 0.03), {});
  EXPECT_NEAR(in.removal_mm3_per_s, 0.8, 1e-12);
  EXPECT_NEAR(in.removal_share[tissueIndex(Material::Enamel)], 0.25, 1e-12);
  EXPECT_NEAR(in.removal_share[tissueIndex(Material::Dentin)], 0.75, 1e-12);
  EXPECT_EQ(in.removal_share[tissueIndex(Material::Caries)], 0.0);
  // Nothing cut: the rate is zero and the shares keep their colour.
  in = feed.next(stateAt(0.2, 0.03, 0.03), {});
  EXPECT_EQ(in.removal_mm3_per_s, 0.0);
  EXPECT_NEAR(in.removal_share[tissueIndex(Material::Dentin)], 0.75, 1e-12);
  // The same time again (a stopped frame): no rate, no division by zero.
  in = feed.next(stateAt(0.2, 0.03, 0.03), {});
  EXPECT_EQ(in.removal_mm3_per_s, 0.0);
}

TEST(SoundFeed, ANewSegmentStartsTheTotalsOver) {
  SoundFeed feed;
  (void)feed.next(stateAt(5.0, 1.0, 0.0), {});
  // A new segment's loop starts at 0 with its own totals: 0.01 mm^3 of dentin in its first 0.1 s.
  const SoundInput in = feed.next(stateAt(0.1, 0.0, 0.01), {});
  EXPECT_NEAR(in.removal_mm3_per_s, 0.1, 1e-12);
  EXPECT_EQ(in.removal_share[tissueIndex(Material::Dentin)], 1.0);
  EXPECT_EQ(in.removal_share[tissueIndex(Material::Enamel)], 0.0);
}

TEST(SoundFeed, ForceAndContactComeFromTheDrill) {
  SoundFeed feed;
  HapticState s = stateAt(0.1, 0.0, 0.0);
  s.tools[size_t(PenRole::Drill)].display.force = {3, 4, 0};
  s.tools[size_t(PenRole::Drill)].contacts = 12;
  s.tools[size_t(PenRole::Mirror)].display.force = {0, 0, 9};  // the mirror is not heard
  const SoundInput in = feed.next(s, {});
  EXPECT_DOUBLE_EQ(in.force_n, 5.0);
  EXPECT_TRUE(in.contact);
  EXPECT_EQ(in.removal_mm3_per_s, 0.0);
}

}  // namespace
}  // namespace dentsim::audio
