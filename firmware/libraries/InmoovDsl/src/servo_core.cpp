#include "servo_core.h"

namespace inmoov {

ServoCore::ServoCore(uint8_t board_id, const ServoSettings* servos, uint8_t count,
                     uint8_t* values, WriteServo write, SendByte send)
    : board_id_(board_id), servos_(servos), count_(count), values_(values), write_(write),
      send_(send), pending_(NONE) {}

void ServoCore::begin() {
  pending_ = NONE;
  for (uint8_t i = 0; i < count_; i++) set(i, servos_[i].rest);
}

void ServoCore::feed(uint8_t byte) {
  if (byte == CANCEL) {
    pending_ = NONE;
  } else if (byte == DUMP) {
    dump();  // a half-read command stays half-read
  } else if (byte >= LOWEST_SIGNAL) {
    // a signal this board does not act on: skipped wherever it arrives
  } else if (pending_ == NONE) {
    pending_ = byte;
  } else {
    int8_t index = index_of(static_cast<uint8_t>(pending_));
    pending_ = NONE;
    if (index >= 0) set(static_cast<uint8_t>(index), byte > MAX_VALUE ? MAX_VALUE : byte);
  }
}

uint8_t ServoCore::angle(uint8_t index, uint8_t value) const {
  const ServoSettings& s = servos_[index];
  uint8_t step = static_cast<uint8_t>(static_cast<uint16_t>(value) * (s.hi - s.lo) / MAX_VALUE);
  return s.reversed ? s.hi - step : s.lo + step;
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
