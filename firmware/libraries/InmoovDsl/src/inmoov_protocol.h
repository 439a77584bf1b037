// The servo boards' byte protocol: every constant defined once for the firmware.
// The same numbers are defined once in Python (inmoov_dsl/protocol.py); a test
// (tests/test_firmware.py) checks the two against each other.
#ifndef INMOOV_PROTOCOL_H
#define INMOOV_PROTOCOL_H

#include <stdint.h>

namespace inmoov {

// Signals: bytes above MAX_VALUE that are not values, numbered down from 255.
enum Signal : uint8_t {
  CANCEL = 255,  // host -> board: drop any half-read command, expect a servo ID
  WAIT = 254,    // board -> host: nothing left to read
  DUMP = 253,    // host -> board: answer START BOARD_ID N (id value)*N END
  START = 252,   // board -> host: a reply begins
  END = 251,     // board -> host: a reply ends
  MIN = 250,     // host -> glove: capture the lower calibration bound
  MAX = 249,     // host -> glove: capture the upper calibration bound
  RELAX = 248,   // host -> servo board: stop driving the servos until the next command
};

const uint8_t MAX_VALUE = 180;       // largest servo value; larger values are clamped
const uint8_t MAX_SERVO_ID = 180;    // servo IDs are values too
const uint8_t FIRST_BOARD_ID = 181;  // board IDs start here
const uint16_t POSE_SETTLE_MS = 1000;  // ms without a servo command before the pose is stored
// host -> servo board where a servo ID is expected, then a number: play that stored
// gesture, or (CATALOG) list them. The original firmware reads a pair for a servo it
// does not have. Not a signal: in value position 247 is a value, as any byte is.
const uint8_t PLAY = 247;
const uint8_t CATALOG = 180;

}  // namespace inmoov

#endif
