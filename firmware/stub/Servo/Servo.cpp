#include "Servo.h"

uint16_t servo_stub_pulse[MAX_SERVOS];
int8_t servo_stub_pin[MAX_SERVOS] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
uint8_t servo_stub_jumps = 0;
static uint8_t servo_count = 0;

Servo::Servo() : min_(MIN_PULSE_WIDTH), max_(MAX_PULSE_WIDTH), written_(false) {
  index_ = servo_count < MAX_SERVOS ? servo_count++ : INVALID_SERVO;
  if (index_ != INVALID_SERVO) servo_stub_pulse[index_] = DEFAULT_PULSE_WIDTH;
}

uint8_t Servo::attach(int pin) { return attach(pin, MIN_PULSE_WIDTH, MAX_PULSE_WIDTH); }

uint8_t Servo::attach(int pin, int min, int max) {
  if (index_ == INVALID_SERVO) return INVALID_SERVO;
  // the real library starts an unwritten servo at 1500 us: a jump to mid-travel
  if (!written_ && servo_stub_pin[index_] < 0) servo_stub_jumps++;
  servo_stub_pin[index_] = static_cast<int8_t>(pin);
  min_ = min;
  max_ = max;
  return index_;
}

void Servo::detach() {
  if (index_ != INVALID_SERVO) servo_stub_pin[index_] = -1;
}

void Servo::write(int value) {
  if (value < MIN_PULSE_WIDTH) {
    if (value < 0) value = 0;
    if (value > 180) value = 180;
    value = min_ + static_cast<long>(value) * (max_ - min_) / 180;
  }
  writeMicroseconds(value);
}

void Servo::writeMicroseconds(int value) {
  if (index_ == INVALID_SERVO) return;
  written_ = true;
  if (value < min_) value = min_;
  if (value > max_) value = max_;
  servo_stub_pulse[index_] = static_cast<uint16_t>(value);
}

int Servo::read() {
  if (index_ == INVALID_SERVO) return 0;
  return static_cast<int>((static_cast<long>(servo_stub_pulse[index_]) - min_) * 180 /
                          (max_ - min_));
}

int Servo::readMicroseconds() { return index_ == INVALID_SERVO ? 0 : servo_stub_pulse[index_]; }

bool Servo::attached() { return index_ != INVALID_SERVO && servo_stub_pin[index_] >= 0; }
