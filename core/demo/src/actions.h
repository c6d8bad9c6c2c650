#pragma once
// The action generators. Each appends one action (or one locomotion step) at
// b.now(), records its ground truth and leaves the body in a known mode.
#include "builder.h"

namespace fray::demo::detail {

// Fighting set (actions_fight.cpp). All start and end in Mode::Guard, except
// toGuard (from Stand) and toStand (to Stand).
void jab(Builder& b);
void cross(Builder& b);
void hook(Builder& b, int side);       // 0 left (lead), 1 right (rear)
void uppercut(Builder& b, int side);
void frontKick(Builder& b);            // rear (right) leg
void roundhouse(Builder& b, int side); // kicking leg
void kneeStrike(Builder& b);           // rear (right) knee
void blockHigh(Builder& b);
void blockLow(Builder& b);
void parry(Builder& b);
void slip(Builder& b, int side);       // head moves to this side
void duck(Builder& b);
void swayBack(Builder& b);
void guardStep(Builder& b, int direction);  // 0 forward, 1 back, 2 left, 3 right
void pivot(Builder& b, int side);           // 0 turn left, 1 turn right
void guardIdle(Builder& b, double seconds);
void toGuard(Builder& b);
void toStand(Builder& b);
void headSnap(Builder& b);
void bodyStagger(Builder& b);
void knockedBack(Builder& b);
void knockedDown(Builder& b);  // hit, fall, lie, get up, back to guard

// Falls (actions_falls.cpp): start in Stand (or Guard), end lying; getUp ends in Stand.
void fallForward(Builder& b);
void fallBackward(Builder& b);
void fallSideways(Builder& b);
void fallPushed(Builder& b);
void getUp(Builder& b);
// Pieces shared with knockedDown. They return the time they end at.
double sitFallBackward(Builder& b, double t0, double k);        // standing -> lying on the back, knees up
double getUpFromSupine(Builder& b, double t0, double k, Mode endMode);

// Locomotion (actions_move.cpp).
enum class Gait : std::uint8_t { Walk, Jog, Run, Backpedal, Carry };
// One step. speed (m/s, along the heading; negative = backwards) and yawRate
// (rad/s) are the targets at the end of the step; `name` is the action kind.
void locoStep(Builder& b, Gait gait, double speed, double yawRate, const char* name);
// The keys of one step without recording an action (locoStep and the
// football cuts build on it): `lateral` m to the left within the step, the
// body leaning `lean` rad into it. Returns the step's end time.
double locoStepKeys(Builder& b, Gait gait, double speed, double yawRate, double lateral, double lean);
// Last step: the swing foot lands beside the other one and the body stops.
void locoStop(Builder& b, Gait gait, const char* name);
void idleStand(Builder& b, double seconds);
// Turning on the spot by small steps (Stand or Carry mode).
void turnInPlace(Builder& b, double angle, const char* name);

// Carrying (actions_carry.cpp): Stand <-> Carry.
void pickUpBox(Builder& b);
void putDown(Builder& b);
void handOver(Builder& b);
void receiveBox(Builder& b);

// One end of a long box, held at both hands, face to face with a second
// carrier (the carry set). Every action lasts kCarryEndStep s.
inline constexpr double kCarryEndStep = 0.8;     // s (48 frames)
inline constexpr double kCarryEndStride = 0.28;  // m per step (+-6 %)
inline constexpr double kCarryEndTurn = 0.20;    // rad per turning step (+-6 %)
inline constexpr double kCarryEndPivot = 1.22;   // m: the box's middle ahead of the base (1.6 m grip span / 2 + grip reach)
enum class CarryEndMove : std::uint8_t { Forward, Back, Left, Right, TurnLeft, TurnRight, Hold, ForwardLeft, ForwardRight, BackLeft, BackRight };
void carryEndLift(Builder& b);  // Stand -> holding the end
void carryEndStep(Builder& b, CarryEndMove move);

// Football (actions_football.cpp), from and back to a run.
void juke(Builder& b, int side);  // a two-step cut 0.6-0.7 m to this side (0 left, 1 right), still running
void tackle(Builder& b);          // one run step, a dive with the arms forward, landing face down (Prone)

}  // namespace fray::demo::detail
