// Servo pulses from the 16-bit timers of the board, written from the datasheets: each
// timer drives several servos, pulsed one after another in one 20 ms frame, each pin
// high for its pulse width (0.5 us ticks: the timer in CTC mode at clk/8), low otherwise.
// An ATmega328P (Uno, Nano) has one such timer for servos, Timer1: 12 servos (twelve
// wide pulses make a frame longer than 20 ms, as with the Servo library). An ATmega2560
// (Mega) has four, taken in the Arduino Servo library's order, Timers 5, 1, 3 and 4, and
// gives each 8 servos, so that its frame is always 20 ms: 32 servos, on any of its
// pins. Channel c is on timer c / PULSE_CHANNELS.
//
// A pin pulses only once it has a width: nothing is sent to a servo before the board
// knows where it must be, so the first pulse is the pose the board starts in. stop()
// silences every pin (a hobby servo goes limp), start() pulses them again.
//
// The timers in use are ours: analogWrite() on their pins does not work beside them
// (9 and 10 on an Uno; 44-46 on a Mega, and 11-12, 2-3-5, 6-8 as more timers are used).
#ifndef INMOOV_SERVO_PULSES_H
#define INMOOV_SERVO_PULSES_H

#include <stdint.h>

namespace inmoov {

const uint16_t FRAME_TICKS = 40000;  // 20 ms in 0.5 us ticks
#if defined(__AVR_ATmega2560__) || defined(__AVR_ATmega1280__)
// servos one timer drives: eight of the widest pulses (2.4 ms) fit in a 20 ms frame, so
// every pin pulses every 20 ms whatever the widths
const uint8_t PULSE_CHANNELS = 8;
const uint8_t PULSE_TIMERS = 4;
#else
const uint8_t PULSE_CHANNELS = 12;  // as the Servo library: Timer1 is the only one free
const uint8_t PULSE_TIMERS = 1;
#endif
const uint8_t MAX_SERVOS = PULSE_CHANNELS * PULSE_TIMERS;  // a board's servos, at most

namespace pulses {

// Channel `channel` (0..MAX_SERVOS-1) drives Arduino pin `pin`: an output, low, with no
// pulse until it has a width. A timer's channels pulse in their order, a frame every 20 ms.
void attach(uint8_t channel, uint8_t pin);
// Start the timers that have channels (after the channels are attached and written).
void begin();
// A channel's pulse width in us (taken at its next pulse).
void write(uint8_t channel, uint16_t us);
// Stop every pin's pulses (pins low) / pulse them again at the widths they have.
void stop();
void start();
// Frames of the first timer begun so far (modulo 256): it counts up once each of its
// channels has pulsed, in the quiet before the next frame.
uint8_t frames();

}  // namespace pulses
}  // namespace inmoov

#endif
