// A servo board's protocol as a pure state machine: feed(byte) reads one byte and
// calls back for each servo write, each byte to send, and to stop or restart the
// pulses. No Arduino dependency: the sketch reads the serial port and drives the
// servos, host tests feed byte timelines.
#ifndef INMOOV_SERVO_CORE_H
#define INMOOV_SERVO_CORE_H

#include <stdint.h>

#include "inmoov_protocol.h"

namespace inmoov {

// One servo of a board, as settings.h declares it.
struct ServoSettings {
  uint8_t id;        // servo ID on the wire, unique in the robot
  uint8_t pin;       // Arduino pin
  uint8_t lo;        // calibration: command 0..180 maps onto lo..hi (servo angles)
  uint8_t hi;
  uint8_t reversed;  // 1: command 180..0 maps onto lo..hi instead
  uint8_t rest;      // command value at the first power-up (nothing stored yet)
};

typedef void (*WriteServo)(uint8_t index, uint8_t angle);  // servo index, servo angle
typedef void (*SendByte)(uint8_t byte);
typedef void (*Drive)(bool on);  // false: stop every servo's pulses; true: pulse again

const uint16_t PULSE_MIN_US = 544;   // pulse width for servo angle 0
const uint16_t PULSE_MAX_US = 2400;  // pulse width for servo angle 180

// The pulse width (us) for a servo angle 0..180, as the Arduino Servo library computes
// it: map(angle, 0, 180, 544, 2400) in integers (split so it fits 16 bits).
inline uint16_t pulse_us(uint8_t angle) {
  return PULSE_MIN_US + 10 * angle + static_cast<uint16_t>(56 * angle) / MAX_VALUE;
}

class ServoCore {
 public:
  // `values` has room for `count` bytes: the last command value of each servo.
  // `drive` may be null (a board that cannot stop its pulses ignores RELAX).
  // (constexpr: a global board is initialised data, not code run at start-up)
  constexpr ServoCore(uint8_t board_id, const ServoSettings* servos, uint8_t count,
                      uint8_t* values, WriteServo write, SendByte send, Drive drive = 0)
      : board_id_(board_id), servos_(servos), count_(count), values_(values), write_(write),
        send_(send), drive_(drive), pending_(NONE), relaxed_(false) {}

  // Every servo to `pose` (the pose stored before a reset) or, if null, to its rest
  // value; called before the pulses start, so each servo's first pulse is its pose.
  void begin(const uint8_t* pose = 0);
  // Read one byte from the host.
  void feed(uint8_t byte);
  // Servo `index` to `value` (0..180) from the board itself (a stored gesture): as a
  // servo command does, it drives every servo again after RELAX.
  void command(uint8_t index, uint8_t value);
  // True when the next byte read is a servo ID (no command half-read).
  bool expects_id() const { return pending_ == NONE; }
  // True after RELAX, until the next servo write.
  bool relaxed() const { return relaxed_; }
  // The servo angle for command `value` on servo `index`: Arduino's map(value, 0, 180,
  // lo, hi), or map(value, 180, 0, lo, hi) for a reversed servo, in integers.
  uint8_t angle(uint8_t index, uint8_t value) const;
  // Index of the servo with `id`, or -1 if this board does not own it.
  int8_t index_of(uint8_t id) const;

  uint8_t value(uint8_t index) const { return values_[index]; }
  uint8_t count() const { return count_; }

 private:
  static const uint16_t NONE = 0x100;  // no servo ID pending
  void set(uint8_t index, uint8_t value);
  void dump();

  uint8_t board_id_;
  const ServoSettings* servos_;
  uint8_t count_;
  uint8_t* values_;
  WriteServo write_;
  SendByte send_;
  Drive drive_;
  uint16_t pending_;  // a servo ID waiting for its value, or NONE
  bool relaxed_;
};

}  // namespace inmoov

#endif
