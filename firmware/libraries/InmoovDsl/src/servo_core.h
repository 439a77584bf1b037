// A servo board's protocol as a pure state machine: feed(byte) reads one byte and
// calls back for each servo write and each byte to send. No Arduino dependency: the
// sketch reads the serial port and drives the servos, host tests feed byte timelines.
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
  uint8_t rest;      // command value at power-up
};

typedef void (*WriteServo)(uint8_t index, uint8_t angle);  // servo index, servo angle
typedef void (*SendByte)(uint8_t byte);

class ServoCore {
 public:
  // `values` has room for `count` bytes: the last command value of each servo.
  ServoCore(uint8_t board_id, const ServoSettings* servos, uint8_t count, uint8_t* values,
            WriteServo write, SendByte send);

  // Every servo to its rest value (write before attach: no jump at power-up).
  void begin();
  // Read one byte from the host.
  void feed(uint8_t byte);
  // True when the next byte read is a servo ID (no command half-read).
  bool expects_id() const { return pending_ == NONE; }
  // The servo angle for command `value` on servo `index`: Arduino's map(), in integers.
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
  uint16_t pending_;  // a servo ID waiting for its value, or NONE
};

}  // namespace inmoov

#endif
