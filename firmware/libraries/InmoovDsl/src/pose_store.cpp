#include "pose_store.h"

namespace inmoov {

uint16_t crc16(uint16_t crc, uint8_t byte) {
  crc ^= static_cast<uint16_t>(byte) << 8;
  for (uint8_t bit = 0; bit < 8; bit++) {
    crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021)
                         : static_cast<uint16_t>(crc << 1);
  }
  return crc;
}

bool PoseStore::valid(uint16_t slot, uint16_t* seq) {
  uint16_t at = address(slot);
  uint16_t crc = key_;
  for (uint8_t i = 0; i < count_ + 2; i++) {
    uint8_t b = read_(at + i);
    if (i >= 2 && b > MAX_VALUE) return false;
    crc = crc16(crc, b);
  }
  uint16_t kept = read_(at + count_ + 2) | static_cast<uint16_t>(read_(at + count_ + 3)) << 8;
  *seq = read_(at) | static_cast<uint16_t>(read_(at + 1)) << 8;
  return crc == kept;
}

bool PoseStore::load(uint8_t* pose) {
  key_ = crc16(crc16(0xFFFF, board_id_), count_);
  for (uint8_t i = 0; i < count_; i++) key_ = crc16(key_, servos_[i].id);
  newest_ = slots_;
  for (uint16_t slot = 0; slot < slots_; slot++) {
    uint16_t seq;
    if (!valid(slot, &seq)) continue;
    // the newest: seq ahead of the best so far, counting modulo 65536
    if (newest_ == slots_ || static_cast<int16_t>(seq - seq_) > 0) {
      newest_ = slot;
      seq_ = seq;
    }
  }
  if (newest_ == slots_) return false;
  for (uint8_t i = 0; i < count_; i++) pose[i] = read_(address(newest_) + 2 + i);
  return true;
}

void PoseStore::changed(uint16_t now) {
  dirty_ = true;
  last_ = now;
}

bool PoseStore::stored(const uint8_t* values) {
  if (newest_ == slots_) return false;
  for (uint8_t i = 0; i < count_; i++) {
    if (read_(address(newest_) + 2 + i) != values[i]) return false;
  }
  return true;
}

void PoseStore::poll(uint16_t now, const uint8_t* values) {
  if (busy()) {
    uint16_t slot = newest_ == slots_ ? 0 : (newest_ + 1) % slots_;
    if (write_(address(slot) + written_, record_[written_]) && ++written_ == size()) {
      newest_ = slot;  // complete: it is the newest record now
    }
    return;
  }
  if (!dirty_ || static_cast<uint16_t>(now - last_) < POSE_SETTLE_MS) return;
  dirty_ = false;
  if (stored(values) || slots_ == 0) return;
  seq_++;
  record_[0] = static_cast<uint8_t>(seq_);
  record_[1] = static_cast<uint8_t>(seq_ >> 8);
  uint16_t crc = crc16(crc16(key_, record_[0]), record_[1]);
  for (uint8_t i = 0; i < count_; i++) {
    record_[2 + i] = values[i];
    crc = crc16(crc, values[i]);
  }
  record_[count_ + 2] = static_cast<uint8_t>(crc);
  record_[count_ + 3] = static_cast<uint8_t>(crc >> 8);
  written_ = 0;
}

}  // namespace inmoov
