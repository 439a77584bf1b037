// Arduino glue of the stored gestures, included by InmoovServoBoard.h when the sketch's
// stored.h defines INMOOV_STORED_GESTURES: the flash, the clock, the buttons, power-up
// and idling around StoredPlayer.
//
// - PLAY N from the host plays gesture N; PLAY CATALOG sends the catalog, a byte at a
//   time as the serial port has room, so the loop never waits.
// - A button (to ground, with the pin's pull-up) plays its gesture once pressed for
//   DEBOUNCE_MS.
// - The boot gesture plays once the board has started and BOOT_QUIET_MS have passed
//   without a byte from the host (a computer that opened the port, and reset the
//   board, is heard first).
// - The idle gesture plays after idle_after() s without a byte from the host, a button
//   or a gesture, and again after as long.
// - When a gesture ends on its own the board sends WAIT.
#ifndef INMOOV_STORED_H_GLUE
#define INMOOV_STORED_H_GLUE

#include <avr/pgmspace.h>

#include "stored_player.h"

const uint16_t BOOT_QUIET_MS = 250;

uint16_t inmoov_positions[SERVO_COUNT];
uint16_t inmoov_speeds[SERVO_COUNT];
uint8_t inmoov_next[SERVO_COUNT];
inmoov::Button inmoov_buttons[8];
uint8_t inmoov_button_count = 0;
uint32_t inmoov_quiet_since = 0;  // ms: the last byte, press or gesture's end
bool inmoov_boot_pending = false;
volatile uint8_t inmoov_playing = 0;  // the player's state (the simulator watches it)

uint8_t inmoov_flash(uint16_t address) { return pgm_read_byte(INMOOV_STORED + address); }

inmoov::StoredPlayer inmoov_player(BOARD_ID, inmoov_flash, &inmoov_core, inmoov_positions,
                                   inmoov_speeds, inmoov_next);

void inmoov_stored_setup() {
  inmoov_button_count = inmoov_player.buttons() > 8 ? 8 : inmoov_player.buttons();
  for (uint8_t k = 0; k < inmoov_button_count; k++) {
    pinMode(inmoov_player.button_pin(k), INPUT_PULLUP);
    inmoov_buttons[k] = inmoov::Button{1, 1, 0};
  }
  inmoov_boot_pending = inmoov_player.boot() != inmoov::StoredPlayer::NONE;
  inmoov_quiet_since = millis();
}

void inmoov_stored_heard(uint8_t byte) {
  inmoov_boot_pending = false;
  inmoov_quiet_since = millis();
  inmoov_player.heard(byte, inmoov_core.expects_id(), micros());
}

bool inmoov_stored_busy() { return inmoov_player.busy(); }

void inmoov_stored_loop() {
  uint32_t now = millis();
  for (uint8_t k = 0; k < inmoov_button_count; k++) {
    uint8_t level = digitalRead(inmoov_player.button_pin(k));
    if (inmoov::debounce(inmoov_buttons[k], level, static_cast<uint16_t>(now))) {
      inmoov_boot_pending = false;
      inmoov_player.play(inmoov_player.button_gesture(k), micros());
    }
  }
  if (inmoov_boot_pending && now - inmoov_quiet_since >= BOOT_QUIET_MS) {
    inmoov_boot_pending = false;
    inmoov_player.play(inmoov_player.boot(), micros());
  }
  uint8_t idle = inmoov_player.idle();
  if (idle != inmoov::StoredPlayer::NONE && !inmoov_player.busy() && !inmoov_boot_pending &&
      now - inmoov_quiet_since >= 1000UL * inmoov_player.idle_after()) {
    inmoov_player.play(idle, micros());
  }
  if (inmoov_player.busy()) inmoov_quiet_since = now;
  if (inmoov_player.poll(micros(), inmoov::pulses::frames())) {
    inmoov_quiet_since = now;
    if (inmoov_core.expects_id() && Serial.available() == 0) Serial.write(inmoov::WAIT);
  }
  for (int16_t b; Serial.availableForWrite() > 0 && (b = inmoov_player.reply()) >= 0;) {
    Serial.write(static_cast<uint8_t>(b));
  }
  inmoov_playing = inmoov_player.state();
}

#endif
