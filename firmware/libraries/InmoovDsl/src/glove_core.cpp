#include "glove_core.h"

namespace inmoov {

GloveCore::GloveCore(const FlexSettings* sensors, uint8_t count, uint8_t deadband,
                     uint16_t* bounds, uint8_t* sent, SendByte send)
    : sensors_(sensors), count_(count), deadband_(deadband), bounds_(bounds), sent_(sent),
      send_(send) {}

void GloveCore::begin() {
  for (uint8_t i = 0; i < count_; i++) {
    bounds_[2 * i] = sensors_[i].lo;
    bounds_[2 * i + 1] = sensors_[i].hi;
    sent_[i] = UNSENT;
  }
}

uint8_t GloveCore::value(uint8_t index, uint16_t reading) const {
  uint16_t low = lo(index), high = hi(index);
  uint8_t v;
  if (high <= low) {
    v = reading > low ? MAX_VALUE : 0;  // a collapsed calibration: a switch, not a ramp
  } else if (reading <= low) {
    v = 0;
  } else if (reading >= high) {
    v = MAX_VALUE;
  } else {
    v = static_cast<uint8_t>(static_cast<uint32_t>(reading - low) * MAX_VALUE / (high - low));
  }
  return sensors_[index].reversed ? MAX_VALUE - v : v;
}

uint8_t GloveCore::update(const uint16_t* readings) {
  uint8_t pairs = 0;
  for (uint8_t i = 0; i < count_; i++) {
    uint8_t v = value(i, readings[i]);
    uint8_t last = sent_[i];
    bool moved = last == UNSENT || (v > last ? v - last : last - v) > deadband_ ||
                 ((v == 0 || v == MAX_VALUE) && v != last);
    if (!moved) continue;
    if (pairs == 0) send_(CANCEL);
    send_(sensors_[i].servo_id);
    send_(v);
    sent_[i] = v;
    pairs++;
  }
  return pairs;
}

void GloveCore::feed(uint8_t byte, const uint16_t* readings) {
  if (byte != MIN && byte != MAX) return;  // the glove takes no other command
  for (uint8_t i = 0; i < count_; i++) bounds_[2 * i + (byte == MAX ? 1 : 0)] = readings[i];
  for (uint8_t i = 0; i < count_; i++) sent_[i] = UNSENT;  // resend on the new scale
}

}  // namespace inmoov
