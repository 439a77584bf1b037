// Servo pulses from Timer1 of an ATmega328P (Arduino Uno, Nano), written from the
// datasheet: up to 12 servos, pulsed one after another in one 20 ms frame, each pin high
// for its pulse width (0.5 us ticks: Timer1 in normal mode at clk/8), low otherwise.
//
// A pin pulses only once it has a width: nothing is sent to a servo before the board
// knows where it must be, so the first pulse is the pose the board starts in. stop()
// silences every pin (a hobby servo goes limp), start() pulses them again.
//
// Timer1 is ours: analogWrite() on pins 9 and 10 does not work beside it.
#ifndef INMOOV_SERVO_PULSES_H
#define INMOOV_SERVO_PULSES_H

#include <stdint.h>

namespace inmoov {

const uint8_t PULSE_CHANNELS = 12;   // servos one timer can drive in a 20 ms frame
const uint16_t FRAME_TICKS = 40000;  // 20 ms in 0.5 us ticks

namespace pulses {

// Channel `channel` (0..11) drives Arduino pin `pin`: an output, low, with no pulse
// until it has a width. Channels pulse in their order, one frame every 20 ms.
void attach(uint8_t channel, uint8_t pin);
// Start Timer1 (after the channels are attached and, ideally, written).
void begin();
// A channel's pulse width in us (taken at its next pulse).
void write(uint8_t channel, uint16_t us);
// Stop every pin's pulses (pins low) / pulse them again at the widths they have.
void stop();
void start();
// Frames begun so far (modulo 256): it counts up once every channel has pulsed, in the
// quiet before the next frame, so a width written then is every channel's next pulse.
uint8_t frames();

}  // namespace pulses
}  // namespace inmoov

#endif
