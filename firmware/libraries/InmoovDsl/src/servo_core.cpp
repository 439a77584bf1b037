#include "servo_core.h"

namespace inmoov {

void ServoCore::begin(const uint8_t* pose) {
  pending_ = NONE;
  relaxed_ = false;
  for (uint8_t i = 0; i < count_; i++) set(i, pose ? pose[i] : servos_[i].rest);
}

// As the original firmware reads bytes: CANCEL and DUMP (and our RELAX) act wherever
// they arrive and drop a half-read command; any other byte is a servo ID where an ID
// is expected, and a value (clamped to 180) where a value is.
void ServoCore::feed(uint8_t byte) {
  if (byte == CANCEL || byte == DUMP || byte == RELAX) {
    pending_ = NONE;
    if (byte == DUMP) dump();
    if (byte == RELAX && drive_ && !relaxed_) {
      relaxed_ = true;
      drive_(false);
    }
  } else if (pending_ == NONE) {
    pending_ = byte;
  } else {
    int8_t index = index_of(static_cast<uint8_t>(pending_));
    pending_ = NONE;
    if (index < 0) return;
    command(static_cast<uint8_t>(index), byte > MAX_VALUE ? MAX_VALUE : byte);
  }
}

void ServoCore::command(uint8_t index, uint8_t value) {
  set(index, value);
  if (relaxed_) {
    relaxed_ = false;
    drive_(true);
  }
}

uint8_t ServoCore::angle(uint8_t index, uint8_t value) const {
  const ServoSettings& s = servos_[index];
  uint8_t from = s.reversed ? MAX_VALUE - value : value;  // map(v, 180, 0, ...) reversed
  return s.lo + static_cast<uint16_t>(from) * (s.hi - s.lo) / MAX_VALUE;
}

int8_t ServoCore::index_of(uint8_t id) const {
  for (uint8_t i = 0; i < count_; i++) {
    if (servos_[i].id == id) return static_cast<int8_t>(i);
  }
  return -1;
}

void ServoCore::set(uint8_t index, uint8_t value) {
  values_[index] = value;
  write_(index, angle(index, value));
}

void ServoCore::dump() {
  send_(START);
  send_(board_id_);
  send_(count_);
  for (uint8_t i = 0; i < count_; i++) {
    send_(servos_[i].id);
    send_(values_[i]);
  }
  send_(END);
}

}  // namespace inmoov
