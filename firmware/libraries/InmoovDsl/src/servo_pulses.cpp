// Timer1 counts at 2 MHz (0.5 us a tick) in CTC mode: it restarts from 0 at each
// compare match A, whose interrupt walks through the channels: each interrupt ends the
// pulse of the channel before, starts the next one, and sets the compare to its width.
// The timer restarts by itself at the match, not when the interrupt runs, so a late
// interrupt delays both edges of a pulse alike and the frame keeps its 20 ms exactly.
#if defined(__AVR__)

#include "servo_pulses.h"

#include <Arduino.h>
#include <avr/interrupt.h>
#include <avr/io.h>

namespace inmoov {
namespace {

struct Channel {
  uint8_t port;    // data-space address of the pin's PORTx register (0: no pin)
  uint8_t mask;    // the pin's bit in it
  uint16_t ticks;  // pulse width; 0: not written yet, the pin stays low
};

const uint8_t NONE = 0xFF;
// The rising edge comes this many ticks later in the interrupt than the falling edge
// (measured in simavr): the compare is set that much later so the width is exact.
const uint8_t EDGE_SKEW_TICKS = 1;

Channel channels_[PULSE_CHANNELS];
uint8_t count_ = 0;         // channels attached (the highest + 1)
volatile bool quiet_ = false;  // stop(): no channel starts a pulse
uint16_t frame_used_;       // ticks of this frame's pulses so far
volatile uint8_t frames_ = 0;  // frames whose pulses are over
// The pin that is high, and the one that goes high at the next compare (port 0: none),
// kept ready so that the interrupt moves both edges within a few cycles of each other.
uint8_t high_ = NONE, high_port_ = 0, high_mask_ = 0;
uint8_t next_ = NONE, next_port_ = 0, next_mask_ = 0;

inline volatile uint8_t& reg(uint8_t address) { return _SFR_MEM8(address); }

// The channel after `from` (NONE: the first) that has a width, made the next to rise.
void plan_next(uint8_t from) {
  uint8_t i = from;
  while (++i < count_ && !quiet_) {  // NONE + 1 == 0
    if (channels_[i].ticks) {
      next_ = i;
      next_port_ = channels_[i].port;
      next_mask_ = channels_[i].mask;
      return;
    }
  }
  next_ = NONE;
  next_port_ = 0;
}

}  // namespace

namespace pulses {

void attach(uint8_t channel, uint8_t pin) {
  if (channel >= PULSE_CHANNELS) return;
  Channel& c = channels_[channel];
  c.port = static_cast<uint8_t>(reinterpret_cast<uintptr_t>(portOutputRegister(digitalPinToPort(pin))));
  c.mask = digitalPinToBitMask(pin);
  reg(c.port) &= ~c.mask;
  reg(c.port - 1) |= c.mask;  // DDRx sits just below PORTx: an output, low
  if (channel >= count_) count_ = channel + 1;
}

void begin() {
  uint8_t sreg = SREG;
  cli();
  TCCR1A = 0;  // CTC mode, TOP = OCR1A (the Arduino core set Timer1 up for PWM)
  TCCR1B = _BV(WGM12) | _BV(CS11);  // clk/8: 0.5 us ticks at 16 MHz
  TCNT1 = 0;
  OCR1A = 32;  // the first frame starts in 16 us
  frame_used_ = 0;
  plan_next(NONE);
  TIFR1 = _BV(OCF1A);  // no stale match
  TIMSK1 |= _BV(OCIE1A);
  SREG = sreg;
}

void write(uint8_t channel, uint16_t us) {
  if (channel >= count_ || !channels_[channel].port) return;  // not attached
  uint16_t ticks = us * 2;
  // computed before interrupts go off: the compiler may not sink the caller's
  // arithmetic (pulse_us's division, inlined) into the section below, where it would
  // hold a servo's edge back by 12 us
  asm volatile("" : "+r"(ticks));
  uint8_t sreg = SREG;
  cli();  // a 16-bit store is two byte stores: not while the interrupt may read it
  channels_[channel].ticks = ticks;
  SREG = sreg;
}

void stop() { quiet_ = true; }

void start() { quiet_ = false; }

uint8_t frames() { return frames_; }

}  // namespace pulses
}  // namespace inmoov

ISR(TIMER1_COMPA_vect) {
  using namespace inmoov;
  if (high_port_) reg(high_port_) &= ~high_mask_;  // a pulse ends...
  if (next_port_) reg(next_port_) |= next_mask_;   // ...and the next begins
  high_ = next_;
  high_port_ = next_port_;
  high_mask_ = next_mask_;
  if (high_ != NONE) {  // it ends a width from now; then the channel after it begins
    uint16_t ticks = channels_[high_].ticks + EDGE_SKEW_TICKS;
    OCR1A = ticks - 1;  // the match comes when the count reaches OCR1A: after OCR1A + 1
    frame_used_ += ticks;
    plan_next(high_);
    return;
  }
  // every channel has pulsed: the next frame starts 20 ms after this one did (or soon,
  // if twelve long pulses took longer than that), with the first channel
  uint16_t rest = frame_used_ < FRAME_TICKS - 200 ? FRAME_TICKS - frame_used_ : 200;
  OCR1A = rest - 1;
  frame_used_ = 0;
  frames_++;
  plan_next(NONE);
}

#endif
