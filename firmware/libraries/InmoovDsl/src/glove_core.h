// The flex-sensor glove as a pure state machine: sensor readings in, servo commands
// out (255 id v id v ... for the servo board, mirrored to the computer), and the MIN
// and MAX signals from the computer capture the calibration bounds. No Arduino
// dependency: the sketch reads the pins and the ports, host tests drive the rest.
#ifndef INMOOV_GLOVE_CORE_H
#define INMOOV_GLOVE_CORE_H

#include <stdint.h>

#include "inmoov_protocol.h"
#include "servo_core.h"

namespace inmoov {

// One flex sensor, as settings.h declares it.
struct FlexSettings {
  uint8_t servo_id;  // the servo it commands
  uint8_t pin;       // analog pin (14 = A0)
  uint16_t lo;       // reading that maps to command 0 (before any MIN capture)
  uint16_t hi;       // reading that maps to command 180
  uint8_t reversed;  // 1: lo maps to 180 and hi to 0
};

class GloveCore {
 public:
  // `bounds` has room for 2 * count readings (the live calibration: lo, hi per sensor),
  // `sent` for count values (the last value sent of each sensor).
  GloveCore(const FlexSettings* sensors, uint8_t count, uint8_t deadband, uint16_t* bounds,
            uint8_t* sent, SendByte send);

  // Back to the settings' calibration; the next update sends every sensor.
  void begin();
  // New readings (one per sensor, 0..1023): sends CANCEL and a pair for every sensor
  // whose value moved more than the dead-band (or reached 0 or 180), nothing if none.
  // Returns how many pairs it sent.
  uint8_t update(const uint16_t* readings);
  // A byte from the computer: MIN / MAX capture `readings` as the lower / upper bound.
  void feed(uint8_t byte, const uint16_t* readings);
  // Command value 0..180 for `reading` of sensor `index`.
  uint8_t value(uint8_t index, uint16_t reading) const;

  uint16_t lo(uint8_t index) const { return bounds_[2 * index]; }
  uint16_t hi(uint8_t index) const { return bounds_[2 * index + 1]; }

 private:
  static const uint8_t UNSENT = 0xFF;

  const FlexSettings* sensors_;
  uint8_t count_;
  uint8_t deadband_;
  uint16_t* bounds_;
  uint8_t* sent_;
  SendByte send_;
};

}  // namespace inmoov

#endif
