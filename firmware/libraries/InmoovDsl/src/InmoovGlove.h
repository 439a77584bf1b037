// Arduino glue of the flex-sensor glove: the sketch includes <SoftwareSerial.h>, its
// settings.h, then this file, and calls inmoov_glove_setup() and inmoov_glove_loop().
// Every FRAME_MS it reads the sensors and sends the servo commands that changed to the
// servo board on the command port (software serial), mirrored to the computer on USB;
// MIN / MAX from the computer capture the calibration bounds. The mapping and the
// dead-band are in GloveCore.
//
// settings.h defines: GLOVE_ID, HOST_BAUD, BOARD_BAUD, COMMAND_RX_PIN, COMMAND_TX_PIN,
// DEADBAND, FRAME_MS, SENSOR_COUNT and SENSORS[SENSOR_COUNT].
#ifndef INMOOV_GLOVE_H
#define INMOOV_GLOVE_H

#include <Arduino.h>
#include <SoftwareSerial.h>

#include "glove_core.h"

SoftwareSerial inmoov_board_port(COMMAND_RX_PIN, COMMAND_TX_PIN);
uint16_t inmoov_bounds[2 * SENSOR_COUNT];
uint8_t inmoov_sent[SENSOR_COUNT];
uint16_t inmoov_readings[SENSOR_COUNT];
unsigned long inmoov_last_frame = 0;  // ms

void inmoov_glove_send(uint8_t byte) {
  inmoov_board_port.write(byte);  // to the servo board
  Serial.write(byte);             // the same stream to the computer
}

inmoov::GloveCore inmoov_glove(SENSORS, SENSOR_COUNT, DEADBAND, inmoov_bounds, inmoov_sent,
                               inmoov_glove_send);

void inmoov_read_sensors() {
  for (uint8_t i = 0; i < SENSOR_COUNT; i++) {
    inmoov_readings[i] = static_cast<uint16_t>(analogRead(SENSORS[i].pin));
  }
}

void inmoov_glove_setup() {
  Serial.begin(HOST_BAUD);
  inmoov_board_port.begin(BOARD_BAUD);
  inmoov_glove.begin();
  inmoov_read_sensors();
}

void inmoov_glove_loop() {
  while (Serial.available() > 0) {
    inmoov_glove.feed(static_cast<uint8_t>(Serial.read()), inmoov_readings);
  }
  unsigned long now = millis();
  if (now - inmoov_last_frame >= FRAME_MS) {
    inmoov_last_frame = now;
    inmoov_read_sensors();
    inmoov_glove.update(inmoov_readings);
  }
}

#endif
