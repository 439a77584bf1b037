#include "stored_player.h"

namespace inmoov {

namespace {

// floor(sqrt(x))
uint16_t isqrt(uint32_t x) {
  uint32_t root = 0, bit = 1UL << 30;
  while (bit > x) bit >>= 2;
  while (bit) {
    if (x >= root + bit) {
      x -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<uint16_t>(root);
}

}  // namespace

bool debounce(Button& b, uint8_t level, uint16_t now) {
  if (level != b.raw) {
    b.raw = level;
    b.since = now;
    return false;
  }
  if (level == b.stable || static_cast<uint16_t>(now - b.since) < DEBOUNCE_MS) return false;
  b.stable = level;
  return level == 0;
}

void StoredPlayer::heard(uint8_t byte, bool id_position, uint32_t now_us) {
  stop();
  reply_size_ = 0;  // a catalog being sent is cut short
  if (asked_) {
    asked_ = false;
    if (byte == CANCEL || byte == DUMP || byte == RELAX) return;
    uint8_t number = byte > MAX_VALUE ? MAX_VALUE : byte;
    if (number == CATALOG) {
      reply_ = 0;
      reply_size_ = 3 + 3 + word(1) + 1;  // START PLAY BOARD, FORMAT LENGTH CATALOG, END
    } else {
      play(number, now_us);
    }
  } else if (id_position && byte == PLAY) {
    asked_ = true;
  }
}

int16_t StoredPlayer::reply() {
  if (reply_ >= reply_size_) return -1;
  uint16_t k = reply_++;
  if (k == 0) return START;
  if (k == 1) return PLAY;
  if (k == 2) return board_id_;
  if (k == reply_size_ - 1) return END;
  return read_(k - 3);
}

void StoredPlayer::stop() { state_ = IDLE; }

void StoredPlayer::play(uint8_t number, uint32_t now_us) {
  if (number >= count()) return;
  uint8_t n = core_->count();
  record_ = word(board_at() + 3 + 4 * n + 2 * number);
  end_us_ = static_cast<uint32_t>(word(record_)) * FRAME_US;
  nibble_ = 0;
  nibbles_ = 2 * word(record_ + 2 + n);
  frame_ = 0;
  mask_ = 0;
  if (core_->relaxed()) core_->command(0, core_->value(0));  // drive the servos again
  bool there = true;
  for (uint8_t j = 0; j < n; j++) {
    positions_[j] = static_cast<uint16_t>(core_->value(j)) * UNIT;
    speeds_[j] = 0;
    there = there && core_->value(j) == read_(record_ + 2 + j);
  }
  state_ = there ? PLAYING : APPROACH;
  t0_ = now_us;
  fresh_ = true;
}

void StoredPlayer::approach_step() {
  uint8_t n = core_->count();
  uint16_t limits = board_at() + 3;
  bool there = true;
  for (uint8_t j = 0; j < n; j++) {
    uint16_t goal = static_cast<uint16_t>(read_(record_ + 2 + j)) * UNIT;
    uint16_t at = positions_[j];
    uint16_t left = goal > at ? goal - at : at - goal;
    if (left == 0) {
      speeds_[j] = 0;
      continue;
    }
    uint32_t accel = word(limits + 4 * j + 2);
    // the fastest speed from which slowing by accel a frame stops within `left`
    uint16_t stop = (isqrt(accel * accel + 8 * accel * left) - accel) / 2;
    uint32_t step = speeds_[j] + accel;
    uint16_t top = word(limits + 4 * j);
    if (step > top) step = top;
    if (step > stop) step = stop;
    if (step > left) step = left;
    positions_[j] = goal > at ? at + step : at - step;
    speeds_[j] = static_cast<uint16_t>(step);
    if (positions_[j] / UNIT != at / UNIT) core_->command(j, positions_[j] / UNIT);
    there = there && positions_[j] == goal;
  }
  if (there) state_ = PLAYING;
}

uint8_t StoredPlayer::nibble() {
  uint8_t b = read_(record_ + 4 + core_->count() + nibble_ / 2);
  return (nibble_++ & 1) ? b & 15 : b >> 4;
}

bool StoredPlayer::decode() {
  uint8_t n = core_->count();
  uint8_t width = (n + 4) / 4;
  if (nibbles_ - nibble_ < width) return false;
  uint32_t head = 0;  // a bit per servo and the flag: up to 28 servos (a Mega's 18)
  for (uint8_t k = 0; k < width; k++) head = head << 4 | nibble();
  uint32_t flag = 1UL << (4 * width - 1);
  if (head & flag) {  // frames without a pair
    frame_ += (head & (flag - 1)) + 1;
    return true;
  }
  mask_ = head;
  for (uint8_t j = 0; j < n; j++) {
    if (!(head >> j & 1)) continue;
    uint8_t code = nibble();
    if (code == 0) {
      next_[j] = nibble() << 4;
      next_[j] |= nibble();
    } else {
      next_[j] = core_->value(j) + (code < 8 ? code - 8 : code - 7);
    }
  }
  return true;
}

bool StoredPlayer::poll(uint32_t now_us, uint8_t frames) {
  if (state_ == APPROACH) {
    if (fresh_ || frames == frames_seen_) {  // a step once each frame's pulses are over
      fresh_ = false;
      frames_seen_ = frames;
      return false;
    }
    frames_seen_ = frames;
    approach_step();
    t0_ = now_us;
    return false;
  }
  if (state_ != PLAYING) return false;
  uint32_t t = now_us - t0_;
  uint8_t n = core_->count();
  uint16_t pair_us = word(board_at() + 1);
  for (;;) {
    if (mask_) {
      uint32_t frame_end = (static_cast<uint32_t>(frame_) + 1) * FRAME_US;
      for (uint8_t j = 0; j < n; j++) {
        if (!(mask_ >> j & 1)) continue;
        if (t + static_cast<uint32_t>(n - 1 - j) * pair_us < frame_end) continue;
        core_->command(j, next_[j]);
        mask_ &= ~(1UL << j);
      }
      if (mask_) return false;
      frame_++;
    }
    if (!decode()) break;
  }
  if (t < end_us_) return false;
  state_ = IDLE;
  return true;
}

}  // namespace inmoov
