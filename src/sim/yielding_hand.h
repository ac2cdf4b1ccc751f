// YieldingHand: a scripted pen held by a hand that gives way to the force the pen renders, so that a scripted student feels guidance and contact as a person would.
//
// A scripted pen (io/pen_playback.h) is rigid: it goes where its script says whatever it is told
// to render, so no force could ever change what a script cuts. A hand is a spring: a grip of
// stiffness H [N/mm] moves by F / H under a force F, after a lag of a few tens of milliseconds.
// YieldingHand wraps any pen that way; the readings it gives are what a session records, so a
// session of a yielding hand replays exactly without it.
#pragma once

#include "core/pen_source.h"
#include "core/rigid.h"

namespace dentsim {

struct HandSettings {
  double stiffness_n_per_mm = 2.0;  // the grip's spring [N/mm]; > 0 (a relaxed hand 0.5, a firm one 5)
  double lag_s = 0.03;              // time constant of the hand's give [s]; > 0
};

class YieldingHand final : public PenSource {
 public:
  // `pen` (not owned) is where the hand means to be.
  YieldingHand(PenSource& pen, const HandSettings& settings) : pen_(pen), settings_(settings) {}

  bool read(double t_s, PenReading* out) override;
  void display(const Wrench& wrench, double t_s) override;
  const Vec3& give() const { return give_; }  // how far the hand has yielded now [mm]

 private:
  PenSource& pen_;
  HandSettings settings_;
  Vec3 force_;           // the latest force rendered [N]
  Vec3 give_;            // the hand's displacement from where it means to be [mm]
  Vec3 give_velocity_;   // [mm/s]
  double last_t_ = 0.0;
  bool started_ = false;
};

}  // namespace dentsim
