// The pose a servo board holds, kept in EEPROM so that it survives a reset or a power
// cut: a pure state machine over two callbacks (read a byte, write a byte if the EEPROM
// is ready), so host tests drive it on an array and the sketch on the real EEPROM.
//
// The EEPROM is a ring of records, one written each time the pose has settled (no
// servo write for POSE_SETTLE_MS) and differs from the newest record:
//
//     seq (2 bytes, little-endian) | value * count | crc (2 bytes)
//
// seq counts up by one per record (modulo 65536), so the newest record is the one with
// the highest seq; each record goes into the slot after the newest, so every cell is
// written once per turn of the ring. crc is CRC-16/CCITT over seq and the values,
// started from a key of the board (its ID and its servos' IDs): a record cut short by a
// power loss, a record of another board's firmware, and an EEPROM never written (0xFF)
// are never read back as a pose. A value above 180 makes a record invalid too.
#ifndef INMOOV_POSE_STORE_H
#define INMOOV_POSE_STORE_H

#include <stdint.h>

#include "servo_core.h"

namespace inmoov {

typedef uint8_t (*ReadEeprom)(uint16_t address);
typedef bool (*WriteEeprom)(uint16_t address, uint8_t byte);  // false: busy, try later

// CRC-16/CCITT (polynomial 0x1021), one byte at a time.
uint16_t crc16(uint16_t crc, uint8_t byte);

class PoseStore {
 public:
  static const uint8_t OVERHEAD = 4;  // bytes of a record besides the values

  // `record` has room for count + OVERHEAD bytes (the record being written).
  // (constexpr: a global store is initialised data, not code run at start-up)
  constexpr PoseStore(uint16_t eeprom_size, uint8_t board_id, const ServoSettings* servos,
                      uint8_t count, uint8_t* record, ReadEeprom read, WriteEeprom write)
      : board_id_(board_id), servos_(servos), count_(count),
        slots_(eeprom_size / (count + OVERHEAD)), record_(record), read_(read),
        write_(write), key_(0), newest_(slots_), seq_(0), written_(count + OVERHEAD),
        dirty_(false), last_(0) {}

  // Find the newest valid record: true and its values in `pose`, or false (none).
  // Called once, at start-up, before the other calls.
  bool load(uint8_t* pose);
  // A servo was written at `now` (ms, modulo 65536): the pose is stored once settled.
  void changed(uint16_t now);
  // Called on every pass of the loop: writes at most one byte, never waits.
  void poll(uint16_t now, const uint8_t* values);

  uint16_t slots() const { return slots_; }
  uint16_t seq() const { return seq_; }     // seq of the newest record
  bool busy() const { return written_ < size(); }  // a record is being written

 private:
  uint8_t size() const { return count_ + OVERHEAD; }
  uint16_t address(uint16_t slot) const { return slot * size(); }
  bool valid(uint16_t slot, uint16_t* seq);
  bool stored(const uint8_t* values);

  uint8_t board_id_;
  const ServoSettings* servos_;
  uint8_t count_;
  uint16_t slots_;
  uint8_t* record_;
  ReadEeprom read_;
  WriteEeprom write_;
  uint16_t key_;      // the CRC's start: the board's ID and its servos' IDs
  uint16_t newest_;   // slot of the newest valid record, or slots_ if none
  uint16_t seq_;
  uint8_t written_;   // bytes of record_ written so far (size(): none pending)
  bool dirty_;        // a servo was written since the last record
  uint16_t last_;     // ms: the last servo write
};

}  // namespace inmoov

#endif
