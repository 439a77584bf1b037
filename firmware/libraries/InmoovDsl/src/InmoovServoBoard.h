// Arduino glue of a servo board: the sketch includes <Servo.h>, its settings.h, then
// this file, and calls inmoov_servo_setup() and inmoov_servo_loop(). The protocol is
// in ServoCore; here are only the port and the servos. Nothing is printed but the
// protocol's own bytes, so nothing can stall the loop.
//
// settings.h defines: BOARD_ID, BAUD, SERVO_COUNT and SERVOS[SERVO_COUNT].
#ifndef INMOOV_SERVO_BOARD_H
#define INMOOV_SERVO_BOARD_H

#include <Arduino.h>
#include <Servo.h>

#include "servo_core.h"

Servo inmoov_servos[SERVO_COUNT];
uint8_t inmoov_values[SERVO_COUNT];
volatile uint16_t inmoov_rx_count = 0;  // bytes read (the simulator checks none is lost)

void inmoov_write_servo(uint8_t index, uint8_t angle) { inmoov_servos[index].write(angle); }
void inmoov_send(uint8_t byte) { Serial.write(byte); }

inmoov::ServoCore inmoov_core(BOARD_ID, SERVOS, SERVO_COUNT, inmoov_values,
                              inmoov_write_servo, inmoov_send);

void inmoov_servo_setup() {
  Serial.begin(BAUD);
  inmoov_core.begin();  // each servo's rest value is written first...
  for (uint8_t i = 0; i < SERVO_COUNT; i++) {
    inmoov_servos[i].attach(SERVOS[i].pin);  // ...so it starts there: no jump at power-up
  }
  Serial.write(inmoov::WAIT);
}

void inmoov_servo_loop() {
  // Drain the receive buffer every pass: it holds 63 bytes, 65 ms at 9600 baud.
  while (Serial.available() > 0) {
    inmoov_core.feed(static_cast<uint8_t>(Serial.read()));
    inmoov_rx_count++;
    if (Serial.available() == 0 && inmoov_core.expects_id()) Serial.write(inmoov::WAIT);
  }
}

#endif
