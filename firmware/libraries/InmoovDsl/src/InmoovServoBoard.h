// Arduino glue of a servo board: the sketch includes its settings.h, then this file, and
// calls inmoov_servo_setup() and inmoov_servo_loop(). The protocol is in ServoCore, the
// pulses in servo_pulses, the stored pose in PoseStore; here are only the port, the
// EEPROM and the clock. Nothing is printed but the protocol's own bytes, so nothing can
// stall the loop.
//
// settings.h defines: BOARD_ID, BAUD, SERVO_COUNT and SERVOS[SERVO_COUNT]. A sketch
// built with stored gestures includes stored.h too (INMOOV_STORED_GESTURES, the
// INMOOV_STORED blob): the board then plays them itself (InmoovStored.h).
#ifndef INMOOV_SERVO_BOARD_H
#define INMOOV_SERVO_BOARD_H

#include <Arduino.h>
#include <avr/eeprom.h>

#include "pose_store.h"
#include "servo_core.h"
#include "servo_pulses.h"

static_assert(SERVO_COUNT <= inmoov::MAX_SERVOS,
              "more servos than this board's timers can pulse (12 on an Uno, 32 on a Mega)");

uint8_t inmoov_values[SERVO_COUNT];
uint8_t inmoov_record[SERVO_COUNT + inmoov::PoseStore::OVERHEAD];
volatile uint16_t inmoov_rx_count = 0;  // bytes read (the simulator checks none is lost)
bool inmoov_written = false;            // a servo was written by the last byte

void inmoov_write_servo(uint8_t index, uint8_t angle) {
  inmoov::pulses::write(index, inmoov::pulse_us(angle));
  inmoov_written = true;
}
void inmoov_drive(bool on) { on ? inmoov::pulses::start() : inmoov::pulses::stop(); }
void inmoov_send(uint8_t byte) { Serial.write(byte); }
uint8_t inmoov_eeprom_read(uint16_t address) {
  return eeprom_read_byte(reinterpret_cast<const uint8_t*>(address));
}
bool inmoov_eeprom_write(uint16_t address, uint8_t byte) {
  if (!eeprom_is_ready()) return false;  // the last byte is still being written (3.3 ms)
  eeprom_update_byte(reinterpret_cast<uint8_t*>(address), byte);  // only if it differs
  return true;
}

inmoov::ServoCore inmoov_core(BOARD_ID, SERVOS, SERVO_COUNT, inmoov_values,
                              inmoov_write_servo, inmoov_send, inmoov_drive);
inmoov::PoseStore inmoov_store(E2END + 1, BOARD_ID, SERVOS, SERVO_COUNT, inmoov_record,
                               inmoov_eeprom_read, inmoov_eeprom_write);

#ifdef INMOOV_STORED_GESTURES
#include "InmoovStored.h"
#else  // no stored gesture: nothing to do
inline void inmoov_stored_setup() {}
inline void inmoov_stored_heard(uint8_t) {}
inline bool inmoov_stored_busy() { return false; }
inline void inmoov_stored_loop() {}
#endif

void inmoov_servo_setup() {
  for (uint8_t i = 0; i < SERVO_COUNT; i++) inmoov::pulses::attach(i, SERVOS[i].pin);
  uint8_t pose[SERVO_COUNT];
  // the pose held before the reset (the rest pose if none is stored), written before
  // the pulses start: every servo's first pulse is already there, nothing jumps
  inmoov_core.begin(inmoov_store.load(pose) ? pose : 0);
  inmoov::pulses::begin();
  Serial.begin(BAUD);
  Serial.write(inmoov::WAIT);
  inmoov_stored_setup();
}

void inmoov_servo_loop() {
  // Drain the receive buffer every pass: it holds 63 bytes, 65 ms at 9600 baud.
  while (Serial.available() > 0) {
    uint8_t byte = static_cast<uint8_t>(Serial.read());
    inmoov_stored_heard(byte);  // any byte stops a stored gesture
    inmoov_core.feed(byte);
    inmoov_rx_count++;
    if (Serial.available() == 0 && inmoov_core.expects_id() && !inmoov_stored_busy()) {
      Serial.write(inmoov::WAIT);
    }
  }
  inmoov_stored_loop();
  uint16_t now = static_cast<uint16_t>(millis());
  if (inmoov_written) {
    inmoov_written = false;
    inmoov_store.changed(now);
  }
  inmoov_store.poll(now, inmoov_values);
}

#endif
