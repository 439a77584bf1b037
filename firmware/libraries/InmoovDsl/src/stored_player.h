// Gestures stored in the board's flash, played by the board itself: a pure state
// machine over a callback that reads the stored bytes (pgm_read_byte on the board, an
// array in the host tests) and the ServoCore it writes through, so DUMP and the stored
// pose see every value it plays. The stored form is inmoov_dsl/wire/stored.py's.
//
// A gesture starts from wherever the hand is: each servo first goes to the gesture's
// start pose, one step a servo frame within its speed and acceleration (the
// approach), then the stream's pairs play at the times the compiler gave them. Any
// byte from the host stops it at once (heard()). PLAY CATALOG sends the catalog.
#ifndef INMOOV_STORED_PLAYER_H
#define INMOOV_STORED_PLAYER_H

#include <stdint.h>

#include "servo_core.h"

namespace inmoov {

typedef uint8_t (*ReadFlash)(uint16_t address);  // a byte of the stored blob

// A push button to ground on a pin with its pull-up: pressed once it reads low for
// DEBOUNCE_MS, released once it reads high as long.
struct Button {
  uint8_t stable;  // 1: released
  uint8_t raw;     // the last reading
  uint16_t since;  // ms: when the reading last changed
};
const uint16_t DEBOUNCE_MS = 20;
// A new reading `level` of `b` at `now` (ms): true when it makes a press.
bool debounce(Button& b, uint8_t level, uint16_t now);

class StoredPlayer {
 public:
  enum State : uint8_t { IDLE = 0, APPROACH = 1, PLAYING = 2 };
  static const uint8_t NONE = 0xFF;      // no gesture (boot, idle)
  static const uint16_t FRAME_US = 20000;
  static const uint8_t UNIT = 64;        // approach positions: 1/64 command degree

  // `positions` and `speeds` have room for the core's count of servos, `next` too.
  constexpr StoredPlayer(uint8_t board_id, ReadFlash read, ServoCore* core,
                         uint16_t* positions, uint16_t* speeds, uint8_t* next)
      : board_id_(board_id), read_(read), core_(core), positions_(positions),
        speeds_(speeds), next_(next), state_(IDLE), asked_(false), reply_(0),
        reply_size_(0), fresh_(false), frames_seen_(0), record_(0), nibble_(0),
        nibbles_(0), frame_(0), mask_(0), t0_(0), end_us_(0) {}

  // A byte from the host (`id_position`: the core expected a servo ID): stops what
  // the board does on its own; PLAY N starts gesture N, PLAY CATALOG the catalog.
  void heard(uint8_t byte, bool id_position, uint32_t now_us);
  // Start gesture `number` (nothing if there is none).
  void play(uint8_t number, uint32_t now_us);
  void stop();
  // Run: an approach step when `frames` (servo frames begun) has moved on, the pairs
  // that are due. True when a gesture has just ended.
  bool poll(uint32_t now_us, uint8_t frames);
  // The catalog's next byte to send, or -1.
  int16_t reply();

  State state() const { return state_; }
  bool busy() const { return state_ != IDLE; }
  uint8_t count() const { return read_(CATALOG_AT); }
  uint8_t boot() const { return read_(CATALOG_AT + 1); }
  uint8_t idle() const { return read_(CATALOG_AT + 2); }
  uint16_t idle_after() const { return word(CATALOG_AT + 3); }
  uint8_t buttons() const { return read_(CATALOG_AT + 5); }
  uint8_t button_pin(uint8_t k) const { return read_(CATALOG_AT + 6 + 2 * k); }
  uint8_t button_gesture(uint8_t k) const { return read_(CATALOG_AT + 7 + 2 * k); }

 private:
  static const uint16_t CATALOG_AT = 3;  // after FORMAT and the catalog's length
  uint16_t word(uint16_t at) const {
    return read_(at) | static_cast<uint16_t>(read_(at + 1)) << 8;
  }
  uint16_t board_at() const { return CATALOG_AT + word(1); }  // servo count, pair_us...
  uint8_t nibble();
  bool decode();  // the next record of the stream; false at its end
  void approach_step();

  uint8_t board_id_;
  ReadFlash read_;
  ServoCore* core_;
  uint16_t* positions_;
  uint16_t* speeds_;
  uint8_t* next_;
  State state_;
  bool asked_;            // PLAY came where an ID was expected: its number is next
  uint16_t reply_;        // catalog bytes sent
  uint16_t reply_size_;   // catalog bytes to send (0: none)
  bool fresh_;            // the approach has not seen a frame yet
  uint8_t frames_seen_;
  uint16_t record_;       // the gesture's record in the blob
  uint16_t nibble_;       // nibbles of its stream read
  uint16_t nibbles_;      // nibbles in its stream
  uint16_t frame_;        // the frame of the record read last
  uint32_t mask_;         // servos of that frame not yet written
  uint32_t t0_;           // us: when the stream started
  uint32_t end_us_;       // us after t0_: the gesture's end
};

}  // namespace inmoov

#endif
