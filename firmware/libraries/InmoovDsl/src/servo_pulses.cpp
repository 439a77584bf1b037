// Each timer counts at 2 MHz (0.5 us a tick) in CTC mode: it restarts from 0 at each
// compare match A, whose interrupt walks through that timer's channels: each interrupt
// ends the pulse of the channel before, starts the next one, and sets the compare to its
// width. The timer restarts by itself at the match, not when the interrupt runs, so a
// late interrupt delays both edges of a pulse alike and the frame keeps its 20 ms exactly.
// (On a Mega an interrupt may wait for another timer's: a few us, on both edges but one.)
#if defined(__AVR__)

#include "servo_pulses.h"

#include <Arduino.h>
#include <avr/interrupt.h>
#include <avr/io.h>

namespace inmoov {
namespace {

struct Channel {
  volatile uint8_t* port;  // the pin's PORTx register (0: no pin)
  uint8_t mask;            // the pin's bit in it
  uint16_t ticks;          // pulse width; 0: not written yet, the pin stays low
};

const uint8_t NONE = 0xFF;
// The rising edge comes this many ticks later in the interrupt than the falling edge
// (measured in simavr): the compare is set that much later so the width is exact.
const uint8_t EDGE_SKEW_TICKS = 1;

// One timer's channels and where its frame is.
struct Timer {
  Channel channels[PULSE_CHANNELS];
  uint8_t count;        // channels attached (the highest + 1)
  uint16_t frame_used;  // ticks of this frame's pulses so far
  // The pin that is high, and the one that goes high at the next compare (0: none),
  // kept ready so that the interrupt moves both edges within a few cycles of each other.
  uint8_t high, next;
  volatile uint8_t *high_port, *next_port;
  uint8_t high_mask, next_mask;
};

Timer timers_[PULSE_TIMERS];
volatile bool quiet_ = false;   // stop(): no channel starts a pulse
volatile uint8_t frames_ = 0;   // frames of the first timer whose pulses are over

// The channel of `t` after `from` (NONE: the first) that has a width, made the next.
inline void plan_next(Timer& t, uint8_t from) {
  uint8_t i = from;
  while (++i < t.count && !quiet_) {  // NONE + 1 == 0
    if (t.channels[i].ticks) {
      t.next = i;
      t.next_port = t.channels[i].port;
      t.next_mask = t.channels[i].mask;
      return;
    }
  }
  t.next = NONE;
  t.next_port = 0;
}

// A compare match of timer `t`, whose compare register is `ocr`: a pulse ends, the next
// begins, and the compare is set to its end (or to the next frame's start).
inline __attribute__((always_inline)) void compare(Timer& t, volatile uint16_t& ocr,
                                                   bool first) {
  if (t.high_port) *t.high_port &= ~t.high_mask;  // a pulse ends...
  if (t.next_port) *t.next_port |= t.next_mask;   // ...and the next begins
  t.high = t.next;
  t.high_port = t.next_port;
  t.high_mask = t.next_mask;
  if (t.high != NONE) {  // it ends a width from now; then the channel after it begins
    uint16_t ticks = t.channels[t.high].ticks + EDGE_SKEW_TICKS;
    ocr = ticks - 1;  // the match comes when the count reaches OCRnA: after OCRnA + 1
    t.frame_used += ticks;
    plan_next(t, t.high);
    return;
  }
  // every channel has pulsed: the next frame starts 20 ms after this one did (or soon,
  // if twelve long pulses on an Uno took longer than that), with the first channel
  uint16_t rest = t.frame_used < FRAME_TICKS - 200 ? FRAME_TICKS - t.frame_used : 200;
  ocr = rest - 1;
  t.frame_used = 0;
  if (first) frames_++;
  plan_next(t, NONE);
}

// Timer k's registers: CTC mode (TOP = OCRnA; the Arduino core set some up for PWM) at
// clk/8, its first frame `delay` ticks from now, its compare A interrupt on.
#define INMOOV_START_TIMER(n, delay)              \
  do {                                            \
    TCCR##n##A = 0;                               \
    TCCR##n##B = _BV(WGM##n##2) | _BV(CS##n##1);  \
    TCNT##n = 0;                                  \
    OCR##n##A = (delay);                          \
    TIFR##n = _BV(OCF##n##A);                     \
    TIMSK##n |= _BV(OCIE##n##A);                  \
  } while (0)

}  // namespace

namespace pulses {

void attach(uint8_t channel, uint8_t pin) {
  if (channel >= MAX_SERVOS) return;
  Timer& t = timers_[channel / PULSE_CHANNELS];
  Channel& c = t.channels[channel % PULSE_CHANNELS];
  c.port = portOutputRegister(digitalPinToPort(pin));
  c.mask = digitalPinToBitMask(pin);
  *c.port &= ~c.mask;
  *(c.port - 1) |= c.mask;  // DDRx sits just below PORTx: an output, low
  if (channel % PULSE_CHANNELS >= t.count) t.count = channel % PULSE_CHANNELS + 1;
}

void begin() {
  uint8_t sreg = SREG;
  cli();
  for (uint8_t k = 0; k < PULSE_TIMERS; k++) {
    timers_[k].frame_used = 0;
    timers_[k].high = NONE;
    plan_next(timers_[k], NONE);
  }
  // the first frame starts in 16 us; the next timers' 1 ms apart, so that their edges
  // seldom fall together (MAX_SERVOS stay within the four)
#if defined(__AVR_ATmega2560__) || defined(__AVR_ATmega1280__)
  INMOOV_START_TIMER(5, 32);
  if (timers_[1].count) INMOOV_START_TIMER(1, 2032);
  if (timers_[2].count) INMOOV_START_TIMER(3, 4032);
  if (timers_[3].count) INMOOV_START_TIMER(4, 6032);
#else
  INMOOV_START_TIMER(1, 32);
#endif
  SREG = sreg;
}

void write(uint8_t channel, uint16_t us) {
  if (channel >= MAX_SERVOS) return;
  Channel& c = timers_[channel / PULSE_CHANNELS].channels[channel % PULSE_CHANNELS];
  if (!c.port) return;  // not attached
  uint16_t ticks = us * 2;
  // computed before interrupts go off: the compiler may not sink the caller's
  // arithmetic (pulse_us's division, inlined) into the section below, where it would
  // hold a servo's edge back by 12 us
  asm volatile("" : "+r"(ticks));
  uint8_t sreg = SREG;
  cli();  // a 16-bit store is two byte stores: not while the interrupt may read it
  c.ticks = ticks;
  SREG = sreg;
}

void stop() { quiet_ = true; }

void start() { quiet_ = false; }

uint8_t frames() { return frames_; }

}  // namespace pulses
}  // namespace inmoov

#if defined(__AVR_ATmega2560__) || defined(__AVR_ATmega1280__)
ISR(TIMER5_COMPA_vect) { inmoov::compare(inmoov::timers_[0], OCR5A, true); }
ISR(TIMER1_COMPA_vect) { inmoov::compare(inmoov::timers_[1], OCR1A, false); }
ISR(TIMER3_COMPA_vect) { inmoov::compare(inmoov::timers_[2], OCR3A, false); }
ISR(TIMER4_COMPA_vect) { inmoov::compare(inmoov::timers_[3], OCR4A, false); }
#else
ISR(TIMER1_COMPA_vect) { inmoov::compare(inmoov::timers_[0], OCR1A, true); }
#endif

#endif
