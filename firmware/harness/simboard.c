/* simboard: a built board image (ATmega328P or ATmega2560 as its ELF says, 16 MHz) running
 * in simavr, fed bytes on
 * its serial port (UART0) at a real link's pace, its pins watched as a servo sees them.
 *
 *   simboard FIRMWARE.elf [options] < timed
 *       Powers the board up, waits for its first WAIT, then sends each "<seconds> <byte>"
 *       line of the input (gestc compile --format timed) at its time, counted from that
 *       WAIT, one byte-time apart at least; then asks for a DUMP. Prints, one per line:
 *         ready S                  when the first WAIT came (s of simulated time)
 *         out S BYTE               every byte the board sent (s after ready)
 *         sent N / read N          bytes sent to the board / bytes its sketch read
 *         dump BOARD N ID V ...    the board's answer to the final DUMP
 *         pin P pulses N first W last W period MIN MAX
 *                                  every pin that pulsed: how many pulses, the width of
 *                                  the first and the last (us), the shortest and longest
 *                                  time from one pulse's start to the next (ms)
 *         pulse P S W              with --pulses: every pulse (pin, start s after ready,
 *                                  width us)
 *         eeprom S ADDRESS BYTE    every EEPROM byte the board changed (s after ready)
 *         cut S                    with --cut: when the power failed
 *       --run-on S       keep running S seconds after the DUMP reply (the board may
 *                        store its pose meanwhile)
 *       --eeprom FILE    the EEPROM's contents at power-up (a missing FILE: a new chip,
 *                        every byte 0xFF), written back to FILE at the end
 *       --cut N          the power fails just after the N-th EEPROM byte written: the run
 *                        ends there, nothing more is sent or asked
 *       --wait S         run S seconds after the last byte before asking for the DUMP
 *                        (default 0.05; a stored gesture stops at any byte)
 *       --button PIN     a push button to ground on PIN, held high as the pin's pull-up
 *                        does (its pin is no servo's: it is not reported)
 *       --press PIN S H  press that button S seconds after ready, for H seconds
 *       --watch SYMBOL   print "watch S VALUE" whenever the byte at SYMBOL (a variable
 *                        of the sketch) changes, S seconds after ready
 *       --flash SYMBOL K B   the image's flash byte K after SYMBOL is B (a table of the
 *                        image changed without building it again)
 *   simboard FIRMWARE.elf --pty [--baud B] [--eeprom FILE] [--log LOG] [--bootloader HEX]
 *       Serves the board on a pseudo-terminal in real time and prints its path. Like an
 *       Uno or a Nano, the board resets when a program opening the port raises DTR: at
 *       the first open (it is powered up then: before, it would speak to nobody), and at
 *       any open after a close that dropped DTR (the closing program left HUPCL set; a
 *       program that clears it leaves DTR up). FILE is written
 *       whenever the EEPROM changes. The UART takes bytes from the pty only 5 ms ahead of
 *       the wire (UART_AHEAD), each as soon as it has room, however late the harness
 *       comes round to it; LOG gets "<seconds> <byte>" for each byte when it starts on
 *       the wire, in the board's own time (simavr's cycles, counted as seconds of
 *       CLOCK_MONOTONIC, Python's time.monotonic, from when the board was powered up).
 *       simavr runs the board after the clock as fast as it can: on a machine too busy
 *       for it to keep up, the board runs late (its answers come late), but what it
 *       receives, and when in its own time, is what the wire brings it. Run as root,
 *       the served board has a higher priority than the programs beside it (BOARD_NICE),
 *       as a real board has a chip of its own.
 *       --control: orders on stdin, a line each:
 *         signal SIGNUM PID [S]  send SIGNUM to PID, at once or once the clock reads S
 *                                (the log's seconds); prints "signalled S N": when (every
 *                                byte taken after it starts on the wire at S or later),
 *                                and N, the bytes taken from the pty until then;
 *       and prints "closed S N" when the program that had the port open has closed it and
 *       every byte it wrote has been taken (and logged).
 *   --bootloader HEX  (either way) an Arduino's bootloader, an Intel hex file (Debian's
 *       arduino-core-avr ships them in hardware/arduino/avr/bootloaders/), in flash beside
 *       the image: every reset starts there, as the BOOTRST fuse makes a real board start,
 *       and the bootloader starts the image when it is done (so "ready" counts its time
 *       from the power-up, and the pins it drives, the LED's, are reported). The reset
 *       flags in MCUSR are the chip's: PORF at power-up, EXTRF at a DTR reset, WDRF at a
 *       watchdog reset. With --pty the port is then a real board's too: the pty starts as
 *       a serial device does (9600 baud, HUPCL set: a program that leaves it set drops DTR
 *       when it closes); the wire runs at the baud the program that has the port open set
 *       (--baud is only where it starts), and a byte sent at another baud than the UART's
 *       arrives as a real UART reads it, either way (a 255 sent at 9600 is a 0 with a
 *       framing error at 115200; the computer reads a framing error as 0).
 *
 * Bytes the board reads are counted by the sketch (inmoov_rx_count), read from RAM.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <pty.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <unistd.h>

#include <simavr/avr_eeprom.h>
#include <simavr/avr_extint.h>
#include <simavr/avr_ioport.h>
#include <simavr/avr_uart.h>
#include <simavr/avr_watchdog.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>
#include <simavr/sim_hex.h>
#include <simavr/sim_regbit.h>

#define F_CPU 16000000ULL
#define UART_AHEAD 0.005 /* s of bytes a UART holds beyond the computer's buffer (pty) */
#define MAX_OUT 1000000

static avr_t *avr;
static avr_irq_t *uart_in;
static avr_cycle_count_t ready_at;  /* cycle of the first WAIT, 0 before */
static int pty_fd = -1;
static struct {
  avr_cycle_count_t cycle;
  uint8_t byte;
} out[MAX_OUT];
static long out_count;
static avr_cycle_count_t byte_cycles;  /* one byte on the wire: 10 bits */
static avr_cycle_count_t wire_free;    /* when the host -> board line is free again */
static uint32_t rx_addr;               /* RAM address of the bytes-read counter, 0 if absent */
static int xoff;                       /* simavr's UART cannot take another byte yet */
static const char *boot_path;          /* --bootloader: its hex file (NULL: none) */
static int reset_seen;                 /* simavr reset the chip (its watchdog fired) */

/* -- the pins, as a servo sees them ------------------------------------------------ */
#define PINS 70 /* Arduino pins: 0..19 on an Uno, 0..69 on a Mega */
/* Each Arduino pin's port and bit, as the core's variants (standard, mega) map them */
static const char UNO_PORTS[] = "DDDDDDDDBBBBBBCCCCCC";
static const char UNO_BITS[] = "01234567012345012345";
static const char MEGA_PORTS[] =
    "EEEEGEHHHHBBBBJJHHDDDDAAAAAAAACCCCCCCCDGGGLLLLLLLLBBBBFFFFFFFFKKKKKKKK";
static const char MEGA_BITS[] =
    "0145533456456710103210012345677654321072107654321032100123456701234567";
static const char *pin_ports = UNO_PORTS, *pin_bits = UNO_BITS;
static int pin_count = 20;
static struct {
  int high;
  avr_cycle_count_t rose; /* the last rising edge */
  long pulses;
  double first_us, last_us, min_period, max_period; /* us, ms */
} pins[PINS];
static int print_pulses;
#define MAX_PULSES 2000000
static struct {
  uint8_t pin;
  avr_cycle_count_t rose;
  float us;
} pulse_log[MAX_PULSES];
static long pulse_count;

/* -- the EEPROM ------------------------------------------------------------------------ */
#define MAX_EEPROM_LOG 100000
static uint8_t *eeprom;      /* simavr's own bytes */
static uint16_t eeprom_size;
static uint8_t shadow[4096]; /* what they were at the last look */
static const char *eeprom_path;
static FILE *byte_log; /* --log: every byte from the pty, when it starts on the wire */
static long eeprom_writes, cut_after = -1;
static avr_cycle_count_t cut_at;
static struct {
  avr_cycle_count_t cycle;
  uint16_t address;
  uint8_t byte;
} eeprom_log[MAX_EEPROM_LOG];

/* -- buttons, watched variables ------------------------------------------------------ */
#define MAX_PRESSES 64
static int button[PINS];       /* a button is on the pin: held high unless pressed */
static struct {
  int pin;
  double at, hold; /* s after ready */
} presses[MAX_PRESSES];
static int press_count;
static const char *watch_name;
static uint32_t watch_addr;
static int watch_last = -1;
#define MAX_WATCH 100000
static struct {
  avr_cycle_count_t cycle;
  uint8_t value;
} watch_log[MAX_WATCH];
static long watch_count;
#define MAX_POKES 16
static struct {
  const char *name;
  uint32_t offset;
  uint8_t byte;
} pokes[MAX_POKES];
static int poke_count;

/* simavr's own messages: errors to stderr, the rest (loading, tracing) dropped, so that
 * stdout carries only what this harness prints. */
static void logger(avr_t *a, const int level, const char *format, va_list ap) {
  (void)a;
  if (level <= LOG_ERROR) vfprintf(stderr, format, ap);
}

static double seconds(avr_cycle_count_t c) { return (double)c / F_CPU; }

/* Seconds from the first WAIT to cycle `c` (negative before it). */
static double since_ready(avr_cycle_count_t c) { return ((double)c - (double)ready_at) / F_CPU; }

static void on_pin(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  int pin = (int)(intptr_t)param;
  if (pin < 0 || pin >= pin_count || button[pin] || (int)(value & 1) == pins[pin].high) return;
  pins[pin].high = value & 1;
  avr_cycle_count_t now = avr->cycle;
  if (pins[pin].high) {
    if (pins[pin].pulses) {
      double period = (double)(now - pins[pin].rose) * 1000.0 / F_CPU;
      if (pins[pin].pulses == 1 || period < pins[pin].min_period) pins[pin].min_period = period;
      if (pins[pin].pulses == 1 || period > pins[pin].max_period) pins[pin].max_period = period;
    }
    pins[pin].rose = now;
    return;
  }
  double us = (double)(now - pins[pin].rose) * 1e6 / F_CPU;
  if (pins[pin].pulses++ == 0) pins[pin].first_us = us;
  pins[pin].last_us = us;
  if (print_pulses && pulse_count < MAX_PULSES) {
    pulse_log[pulse_count].pin = (uint8_t)pin;
    pulse_log[pulse_count].rose = pins[pin].rose;
    pulse_log[pulse_count].us = (float)us;
    pulse_count++;
  }
}

static void save_eeprom(void) {
  if (!eeprom_path) return;
  FILE *f = fopen(eeprom_path, "wb");
  if (!f || fwrite(eeprom, 1, eeprom_size, f) != eeprom_size) perror("simboard: eeprom");
  if (f) fclose(f);
}

/* Every EEPROM_LOOK cycles: which EEPROM bytes changed since the last look, in address
 * order (simavr writes a byte at once, where a real one takes 3.3 ms). With --cut, the
 * bytes after the N-th are put back: the power failed before they were written. */
#define EEPROM_LOOK 1600 /* cycles: 100 us */
static void push_buttons(avr_cycle_count_t when);

static void look_at_watch(avr_cycle_count_t when) {
  if (!watch_addr || avr->data[watch_addr] == watch_last) return;
  watch_last = avr->data[watch_addr];
  if (watch_count < MAX_WATCH) {
    watch_log[watch_count].cycle = when;
    watch_log[watch_count].value = (uint8_t)watch_last;
    watch_count++;
  }
}

static avr_cycle_count_t look_at_eeprom(avr_t *a, avr_cycle_count_t when, void *param) {
  (void)a, (void)param;
  look_at_watch(when);
  push_buttons(when);
  if (memcmp(eeprom, shadow, eeprom_size) == 0) return when + EEPROM_LOOK;
  int changed = 0;
  for (uint16_t k = 0; k < eeprom_size; k++) {
    if (eeprom[k] == shadow[k]) continue;
    if (cut_at) { /* written after the power failed: it never was */
      eeprom[k] = shadow[k];
      continue;
    }
    shadow[k] = eeprom[k];
    changed = 1;
    if (eeprom_writes < MAX_EEPROM_LOG) {
      eeprom_log[eeprom_writes].cycle = when;
      eeprom_log[eeprom_writes].address = k;
      eeprom_log[eeprom_writes].byte = eeprom[k];
    }
    if (++eeprom_writes == cut_after) cut_at = when;
  }
  if (changed && pty_fd >= 0) save_eeprom();
  return when + EEPROM_LOOK;
}

/* -- a wire at another baud than the UART's (with --bootloader) ----------------------- */
#define UCSR0A 0xC0 /* UART0's registers, at the same addresses on both microcontrollers */
#define UBRR0L 0xC4
#define UBRR0H 0xC5
static long wire_baud; /* the computer's end of the wire: --baud, or what the pty was set to */

/* The baud UART0 runs at, as its registers set it (U2X0 halves the divider). */
static long uart_baud(void) {
  unsigned ubrr = (unsigned)(avr->data[UBRR0H] & 0x0F) << 8 | avr->data[UBRR0L];
  return (long)(F_CPU / ((avr->data[UCSR0A] & 2 ? 8 : 16) * (ubrr + 1)));
}

/* The line's level `x` bit-times into an 8N1 frame of `byte` (idle before and after). */
static int level(uint8_t byte, double x) {
  if (x < 0 || x >= 9) return 1;
  return x < 1 ? 0 : (byte >> ((int)x - 1)) & 1;
}

/* What a UART at `to` baud reads of one 8N1 frame of `byte` sent at `from` baud, the line
 * idle before and after: up to 5 bytes (with UART_INPUT_FE when the stop bit was low),
 * each with when its start bit came (s into the frame). Within 4% of each other, a UART's
 * tolerance, the byte is read as sent. Otherwise each falling edge of the line may start
 * a frame: the receiver samples the middle of each of its bits (a start bit high again
 * is no start) and, its stop bit sampled, waits for the next falling edge. A 255 sent at
 * 9600 is one 0 with a framing error at 115200, one 224 at 57600. */
static int garble(uint8_t byte, long from, long to, uint16_t got[5], double when[5]) {
  if (labs(to - from) * 25 <= from) {
    got[0] = byte;
    when[0] = 0;
    return 1;
  }
  double bit = 1.0 / (double)from, its = 1.0 / (double)to; /* s per bit, sent and read */
  int n = 0;
  double edge = 0, after; /* the start bit's falling edge */
  for (;;) {
    if (n < 5 && !level(byte, (edge + 0.5 * its) / bit)) { /* a start bit: a frame is read */
      uint16_t v = 0;
      for (int k = 0; k < 8; k++)
        v |= (uint16_t)(level(byte, (edge + (k + 1.5) * its) / bit) << k);
      if (!level(byte, (edge + 9.5 * its) / bit)) v |= UART_INPUT_FE;
      got[n] = v;
      when[n++] = edge;
      after = edge + 9.5 * its;
    } else
      after = edge + 0.5 * its;
    int k = 1; /* the next falling edge: bit k low after bit k - 1 high */
    while (k <= 8 && (k * bit <= after || !level(byte, k - 0.5) || level(byte, k + 0.5))) k++;
    if (k > 8) return n;
    edge = k * bit;
  }
}

static void on_output(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  if (!ready_at && value == 254) ready_at = avr->cycle;
  if (pty_fd >= 0 && boot_path) { /* the computer reads at its own baud; a framing error as 0 */
    uint16_t got[5];
    double when[5];
    int n = garble((uint8_t)value, uart_baud(), wire_baud, got, when);
    for (int k = 0; k < n; k++) {
      uint8_t b = got[k] & UART_INPUT_FE ? 0 : (uint8_t)got[k];
      if (write(pty_fd, &b, 1) < 0 && errno != EIO && errno != EAGAIN) perror("simboard: pty");
    }
  } else if (pty_fd >= 0) {
    uint8_t b = (uint8_t)value;
    if (write(pty_fd, &b, 1) < 0 && errno != EIO && errno != EAGAIN) perror("simboard: pty");
  } else if (out_count < MAX_OUT) {
    out[out_count].cycle = avr->cycle;
    out[out_count].byte = (uint8_t)value;
    out_count++;
  }
}

static void on_xoff(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq, (void)value, (void)param;
  xoff = 1;
}

static void on_xon(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq, (void)value, (void)param;
  xoff = 0;
}

/* A level from outside on Arduino pin `pin` (a button's contact, or its pull-up). */
static avr_irq_t *pin_irq(int pin) {
  return avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ(pin_ports[pin]), pin_bits[pin] - '0');
}

static void drive_pin(int pin, int level) { avr_raise_irq(pin_irq(pin), level); }

static void release_buttons(void) {
  for (int pin = 0; pin < pin_count; pin++)
    if (button[pin]) drive_pin(pin, 1);
}

/* Press or release the buttons whose time has come (--press): each is pressed at its
 * time and released `hold` s later. */
static int press_state[MAX_PRESSES]; /* 0: not yet, 1: pressed, 2: released */
static void push_buttons(avr_cycle_count_t when) {
  if (!ready_at) return;
  double t = since_ready(when);
  for (int k = 0; k < press_count; k++) {
    if (press_state[k] == 0 && t >= presses[k].at) {
      drive_pin(presses[k].pin, 0);
      press_state[k] = 1;
    } else if (press_state[k] == 1 && t >= presses[k].at + presses[k].hold) {
      drive_pin(presses[k].pin, 1);
      press_state[k] = 2;
    }
  }
}

static void after_reset(void);

/* Run the board until `cycle`: 0, or CUT when the power failed (--cut), -1 if it crashed. */
#define CUT 1
static int run_until(avr_cycle_count_t cycle) {
  while (avr->cycle < cycle) {
    if (cut_at) return CUT;
    int state = avr_run(avr);
    if (reset_seen) after_reset(); /* the watchdog reset the chip (optiboot leaves so) */
    if (state == cpu_Done || state == cpu_Crashed) {
      fprintf(stderr, "simboard: the board stopped (%s)\n",
              state == cpu_Done ? "done" : "crashed");
      return -1;
    }
  }
  return 0;
}

/* simavr 1.6 counts 11 bits for an 8N1 byte: its UART would deliver a continuous
 * stream 10% slower than the wire sends it. Once the sketch has set its baud, the
 * UART's byte-time is made the wire's 10 bits, so a stream with no gaps arrives as a
 * real UART receives it (and simavr's input queue never has to hold bytes back). With
 * --bootloader the wire may run at another baud than the UART: it takes 10 bits of its
 * own baud. */
static void exact_uart(void) {
  avr_cycle_count_t cycles =
      boot_path ? (avr_cycle_count_t)(10 * F_CPU / uart_baud()) : byte_cycles;
  for (avr_io_t *io = avr->io_port; io; io = io->next) {
    if (io->kind && strcmp(io->kind, "uart") == 0 && ((avr_uart_t *)io)->name == '0') {
      avr_uart_t *uart = (avr_uart_t *)io;
      if (uart->cycles_per_byte && uart->cycles_per_byte != cycles)
        uart->cycles_per_byte = cycles;
    }
  }
}

/* Put one byte on the wire: it reaches the UART no sooner than a byte-time after the
 * previous one (simavr adds the byte's own transmission time), and not while simavr's
 * UART still holds bytes it has not delivered. What the board's sketch does with them
 * is what is tested. */
static int send_byte(uint8_t byte, avr_cycle_count_t at) {
  exact_uart();
  if (at < wire_free) at = wire_free;
  int r = run_until(at);
  while (!r && xoff) r = run_until(avr->cycle + 100);
  if (r) return r;
  if (boot_path) { /* what the UART reads of it at its own baud */
    uint16_t got[5];
    double when[5];
    int n = garble(byte, wire_baud, uart_baud(), got, when);
    for (int k = 0; k < n && !r; k++) {
      if (k) r = run_until(at + (avr_cycle_count_t)(when[k] * F_CPU));
      if (!r) avr_raise_irq(uart_in, got[k]);
    }
    wire_free = at + byte_cycles;
    return r;
  }
  avr_raise_irq(uart_in, byte);
  wire_free = at + byte_cycles;
  return 0;
}

static uint16_t read_u16(uint32_t addr) {
  return addr ? (uint16_t)(avr->data[addr] | avr->data[addr + 1] << 8) : 0;
}

static uint32_t find_symbol(elf_firmware_t *fw, const char *name) {
  for (uint32_t i = 0; i < fw->symbolcount; i++) {
    if (strcmp(fw->symbol[i]->symbol, name) == 0) {
      uint32_t addr = fw->symbol[i]->addr;
      return addr >= 0x800000 ? addr - 0x800000 : addr;
    }
  }
  return 0;
}

/* External interrupts sit on pins that drive servos (INT0 and INT1 on an Uno's 2 and 3,
 * INT4 and INT5 on a Mega's): held low between pulses, a "strict" level trigger has
 * simavr poll them on every cycle (6x slower). The images use no external interrupt.
 * (A reset sets them strict again.) */
static void relax_level_triggers(void) {
  for (uint8_t k = 0; k < EXTINT_COUNT; k++) avr_extint_set_strict_lvl_trig(avr, k, 0);
}

/* The microcontroller an ELF image is built for, from its header's flags (avr-gcc's
 * EF_AVR_MACH: 5 for an ATmega328P, 6 for an ATmega2560). */
static const char *mcu_of(const char *path) {
  unsigned char head[40];
  FILE *f = fopen(path, "rb");
  size_t n = f ? fread(head, 1, sizeof head, f) : 0;
  if (f) fclose(f);
  return n == sizeof head && (head[36] & 0x7F) == 6 ? "atmega2560" : "atmega328p";
}

/* The watchdog's control register (WDTCSR) of the ATmega328P and the ATmega2560, its
 * timeout bits (WDP3..0) and its enable bits (WDIE, WDE). */
#define WDTCSR 0x60
#define WDT_TIMEOUT 0x27
#define WDT_ON 0x48
static uint8_t wdt_timeout; /* the timeout bits last written */

/* simavr 1.6 does not apply a new timeout written while the watchdog runs before the next
 * WDR (it compares the timeout bits with themselves once written). optiboot shortens the
 * timeout to 16 ms to leave for the image (after a byte that is none of its commands,
 * and when an upload ends), right after a WDR: a real chip resets 16 ms later, simavr's
 * would wait out the whole second before. The watchdog starts its new timeout here. */
static void on_wdtcsr(struct avr_t *a, avr_io_addr_t addr, uint8_t v, void *param) {
  (void)addr, (void)v, (void)param;
  uint8_t timeout = a->data[WDTCSR] & WDT_TIMEOUT;
  if (timeout != wdt_timeout && (a->data[WDTCSR] & WDT_ON))
    avr_ioctl(a, AVR_IOCTL_WATCHDOG_RESET, NULL);
  wdt_timeout = timeout;
}

/* After any reset: simavr forgot its cycle timers (the EEPROM watch starts again) and set
 * the level triggers strict again; the buttons' pull-ups are held again. */
static void after_reset(void) {
  reset_seen = 0;
  wdt_timeout = avr->data[WDTCSR] & WDT_TIMEOUT;
  relax_level_triggers();
  release_buttons();
  ready_at = 0;
  for (int pin = 0; pin < PINS; pin++) pins[pin].high = 0;
  avr_cycle_timer_register(avr, EEPROM_LOOK, look_at_eeprom, NULL);
}

/* simavr resets the chip itself when its watchdog fires (optiboot leaves for the image
 * that way): every reset goes through the core's reset, where this marks it, so that
 * run_until sets up again what the harness set up (after_reset). */
static void (*core_reset)(struct avr_t *);
static void on_reset(struct avr_t *a) {
  if (core_reset) core_reset(a);
  reset_seen = 1;
}

/* MCUSR, the chip's reset flags: each reset sets the flag of its cause and keeps the flags
 * the software has not cleared; a power-up clears the others. A bootloader reads them:
 * optiboot stays only after an external reset (EXTRF), stk500v2 leaves at once after a
 * watchdog reset (WDRF). simavr 1.6 sets PORF at power-up (avr_init) and WDRF at a
 * watchdog reset, but clears the register on every reset it is asked for. */
static uint8_t reset_flags(void) {
  return avr->reset_flags.extrf.reg ? avr->data[avr->reset_flags.extrf.reg] : 0;
}

/* A reset by DTR (the board's RESET pin): the board starts again, at the bootloader if it
 * has one; RAM and registers do not survive, the EEPROM does; EXTRF is added to MCUSR. */
static void reset_board(void) {
  uint8_t flags = reset_flags();
  avr_reset(avr);
  if (avr->reset_flags.extrf.reg) {
    avr->data[avr->reset_flags.extrf.reg] = flags;
    avr_regbit_set(avr, avr->reset_flags.extrf);
  }
  after_reset();
}

/* simavr's reader of a hex file, its complaints kept back: it says "unsupported" of the
 * start-address record (type 03) that the bootloaders' hexes end with, a record they
 * need not (the BOOTRST fuse says where a reset starts): that one is dropped. Any
 * other complaint (a bad checksum: simavr stops reading there) is passed on, and fails. */
static int read_hex(const char *path, ihex_chunk_p *chunks) {
  fflush(stderr);
  FILE *said = tmpfile();
  int saved = said ? dup(2) : -1;
  if (saved < 0) return read_ihex_chunks(path, chunks);
  dup2(fileno(said), 2);
  int n = read_ihex_chunks(path, chunks);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  rewind(said);
  char line[512];
  while (fgets(line, sizeof line, said)) {
    if (strstr(line, "unsupported check type 03")) continue;
    fputs(line, stderr);
    n = -1;
  }
  fclose(said);
  return n;
}

/* The bootloader (--bootloader) in flash where its hex puts it (an Uno's optiboot at
 * 0x7E00, the old Nano's ATmegaBOOT at 0x7800, a Mega's stk500v2 at 0x3E000), and every
 * reset starting at its first byte, as the BOOTRST fuse has a real board start. The
 * image must end below it, as the bootloader leaves a sketch only the flash below. */
static int load_bootloader(elf_firmware_t *fw, const char *mcu) {
  ihex_chunk_p chunks = NULL;
  int n = read_hex(boot_path, &chunks);
  if (n <= 0) {
    fprintf(stderr, "simboard: cannot read the bootloader %s\n", boot_path);
    return -1;
  }
  uint32_t start = avr->flashend + 1;
  for (int k = 0; k < n; k++) {
    if (chunks[k].baseaddr + chunks[k].size > avr->flashend + 1) {
      fprintf(stderr, "simboard: %s does not fit the flash of an %s: it ends at 0x%X, the "
              "flash at 0x%X\n", boot_path, mcu, chunks[k].baseaddr + chunks[k].size,
              avr->flashend + 1);
      free_ihex_chunks(chunks);
      return -1;
    }
    memcpy(avr->flash + chunks[k].baseaddr, chunks[k].data, chunks[k].size);
    if (chunks[k].baseaddr < start) start = chunks[k].baseaddr;
  }
  free_ihex_chunks(chunks);
  if (fw->flashbase + fw->flashsize > start) {
    fprintf(stderr, "simboard: the image reaches 0x%X, where the bootloader %s starts\n",
            fw->flashbase + fw->flashsize, boot_path);
    return -1;
  }
  avr->reset_pc = start;
  avr->pc = start;                /* the power-up (avr_init's reset) starts there too */
  avr->codeend = avr->flashend; /* code runs above the image now */
  return 0;
}

static int load(const char *path, elf_firmware_t *fw) {
  avr_global_logger_set(logger);
  memset(fw, 0, sizeof *fw);
  if (elf_read_firmware(path, fw) != 0) {
    fprintf(stderr, "simboard: cannot read %s\n", path);
    return -1;
  }
  const char *mcu = mcu_of(path);
  avr = avr_make_mcu_by_name(mcu);
  if (!avr) return -1;
  int mega = strcmp(mcu, "atmega2560") == 0;
  pin_ports = mega ? MEGA_PORTS : UNO_PORTS;
  pin_bits = mega ? MEGA_BITS : UNO_BITS;
  pin_count = mega ? 70 : 20;
  for (int pin = pin_count; pin < PINS; pin++)
    if (button[pin]) {
      fprintf(stderr, "simboard: %s has no pin %d\n", path, pin);
      return -1;
    }
  avr_init(avr);
  avr->log = 0;
  avr_load_firmware(avr, fw);
  avr->frequency = F_CPU;
  core_reset = avr->reset;
  avr->reset = on_reset;
  if (avr->reset_flags.porf.reg) avr_regbit_set(avr, avr->reset_flags.porf); /* powered up */
  if (boot_path && load_bootloader(fw, mcu) < 0) return -1;
  if (boot_path) avr_register_io_write(avr, WDTCSR, on_wdtcsr, NULL); /* after simavr's */
  relax_level_triggers();
  uint32_t flags = 0;
  avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~AVR_UART_FLAG_STDIO;
  /* simavr sleeps 1 us (60 us, as the system's timer goes) at every look at an idle UART's
   * status: a bootloader waiting for a byte looks at it in a loop, and would run at a
   * sixtieth of its speed, far behind the clock of a port served in real time */
  if (boot_path) flags &= ~AVR_UART_FLAG_POLL_SLEEP;
  avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
                          on_output, NULL);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF),
                          on_xoff, NULL);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON),
                          on_xon, NULL);
  rx_addr = find_symbol(fw, "inmoov_rx_count");
  if (watch_name && !(watch_addr = find_symbol(fw, watch_name))) {
    fprintf(stderr, "simboard: %s has no variable %s\n", path, watch_name);
    return -1;
  }
  for (int k = 0; k < poke_count; k++) {
    uint32_t at = find_symbol(fw, pokes[k].name);
    if (!at || at + pokes[k].offset >= avr->flashend) {
      fprintf(stderr, "simboard: %s has no flash table %s\n", path, pokes[k].name);
      return -1;
    }
    avr->flash[at + pokes[k].offset] = pokes[k].byte;
  }
  release_buttons();
  for (int pin = 0; pin < pin_count; pin++)
    avr_irq_register_notify(pin_irq(pin), on_pin, (void *)(intptr_t)pin);
  avr_eeprom_desc_t desc = {.ee = NULL, .offset = 0, .size = 0};
  avr_ioctl(avr, AVR_IOCTL_EEPROM_GET, &desc);
  eeprom = desc.ee;
  eeprom_size = mega ? 4096 : 1024;
  memset(eeprom, 0xFF, eeprom_size); /* a new chip */
  FILE *f = eeprom_path ? fopen(eeprom_path, "rb") : NULL;
  if (f) {
    size_t n = fread(eeprom, 1, eeprom_size, f);
    fclose(f);
    if (n != eeprom_size) {
      fprintf(stderr, "simboard: %s: expected %u bytes of EEPROM, got %zu\n", eeprom_path,
              eeprom_size, n);
      return -1;
    }
  }
  memcpy(shadow, eeprom, eeprom_size);
  avr_cycle_timer_register(avr, EEPROM_LOOK, look_at_eeprom, NULL);
  return 0;
}

static int wait_ready(void) {
  avr_cycle_count_t limit = avr->cycle + 2 * F_CPU;
  while (!ready_at && avr->cycle < limit) {
    if (run_until(avr->cycle + 1000) < 0) return -1;
  }
  if (!ready_at) {
    fprintf(stderr, "simboard: the board sent no WAIT within 2 s\n");
    return -1;
  }
  return 0;
}

static void report(long sent, long before_dump, int cut) {
  printf("ready %.6f\n", seconds(ready_at));
  for (long k = 0; k < out_count; k++)
    printf("out %.6f %d\n", since_ready(out[k].cycle), out[k].byte);
  printf("sent %ld\nread %u\n", sent, read_u16(rx_addr));
  for (long k = before_dump; k < out_count && !cut; k++) {
    if (out[k].byte != 252 || k + 2 >= out_count) continue;
    int n = out[k + 2].byte;
    if (k + 3 + 2 * n >= out_count || out[k + 3 + 2 * n].byte != 251) continue;
    printf("dump %d %d", out[k + 1].byte, n);
    for (int i = 0; i < 2 * n; i++) printf(" %d", out[k + 3 + i].byte);
    printf("\n");
    break;
  }
  for (int pin = 0; pin < PINS; pin++) {
    if (!pins[pin].pulses) continue;
    printf("pin %d pulses %ld first %.2f last %.2f period %.4f %.4f\n", pin, pins[pin].pulses,
           pins[pin].first_us, pins[pin].last_us, pins[pin].min_period,
           pins[pin].max_period);
  }
  for (long k = 0; k < pulse_count; k++)
    printf("pulse %d %.6f %.2f\n", pulse_log[k].pin, since_ready(pulse_log[k].rose),
           pulse_log[k].us);
  for (long k = 0; k < eeprom_writes && k < MAX_EEPROM_LOG; k++)
    printf("eeprom %.6f %u %u\n", since_ready(eeprom_log[k].cycle), eeprom_log[k].address,
           eeprom_log[k].byte);
  for (long k = 0; k < watch_count; k++)
    printf("watch %.6f %u\n", since_ready(watch_log[k].cycle), watch_log[k].value);
  if (cut) printf("cut %.6f\n", since_ready(cut_at));
}

static int script(double run_on, double wait) {
  if (wait_ready() < 0) return 1;
  long sent = 0, before_dump = out_count;
  double t;
  int byte, r = 0;
  avr_cycle_count_t last = ready_at;
  while (!r && scanf("%lf %d", &t, &byte) == 2) {
    if (byte < 0 || byte > 255 || t < 0) {
      fprintf(stderr, "simboard: bad line: %f %d\n", t, byte);
      return 1;
    }
    last = ready_at + (avr_cycle_count_t)(t * F_CPU + 0.5);
    r = send_byte((uint8_t)byte, last);
    sent += !r;
  }
  if (!r) { /* the stream is over: let it settle (replies end), then ask for the values */
    avr_cycle_count_t then = last + (avr_cycle_count_t)(wait * F_CPU);
    r = run_until(then);
    before_dump = out_count;
    if (!r) r = send_byte(253, then);
    sent += !r;
  }
  avr_cycle_count_t limit = avr->cycle + F_CPU / 5;
  for (int ended = 0; !r && !ended && avr->cycle < limit;) {
    r = run_until(avr->cycle + 1000);
    for (long k = before_dump; k < out_count && !ended; k++) ended = out[k].byte == 251;
  }
  if (!r) r = run_until(avr->cycle + byte_cycles * 4);
  if (!r) r = run_until(avr->cycle + (avr_cycle_count_t)(run_on * F_CPU));
  if (r < 0) return 1;
  report(sent, before_dump, r == CUT);
  save_eeprom();
  return 0;
}

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec / 1e9;
}

/* Does the program that has the pty open want DTR dropped when it closes (HUPCL)? The
 * pty's settings are the ones the program set on its side; they stay as the last program
 * left them after it closed the port (avrdude puts back the ones it found as it closes). */
static int hupcl(int master) {
  struct termios tio;
  return tcgetattr(master, &tio) == 0 ? (tio.c_cflag & HUPCL) != 0 : 1;
}

/* The baud the program that has the pty open set on it (0: one not in this table). */
static long port_baud(int master) {
  static const struct {
    speed_t speed;
    long baud;
  } bauds[] = {{B1200, 1200},     {B2400, 2400},     {B4800, 4800},     {B9600, 9600},
               {B19200, 19200},   {B38400, 38400},   {B57600, 57600},   {B115200, 115200},
               {B230400, 230400}, {B460800, 460800}, {B500000, 500000}, {B1000000, 1000000}};
  struct termios tio;
  if (tcgetattr(master, &tio) != 0) return 0;
  speed_t speed = cfgetospeed(&tio);
  for (size_t k = 0; k < sizeof bauds / sizeof bauds[0]; k++)
    if (bauds[k].speed == speed) return bauds[k].baud;
  return 0;
}

/* -- serving the board on a pty --------------------------------------------------------
 * Two clocks: the computer's (CLOCK_MONOTONIC) and the board's (simavr's cycle count),
 * counted from the same moment, so that a cycle is a time in the log's seconds. Two
 * threads: the line, which waits on the pty and takes each byte as a UART would, placing
 * it on the wire at the board's time when a UART would have started it (after the byte
 * before it, and not before it came); and the board, which simavr runs after the clock as
 * fast as it can, reading each byte when its own time comes to it. On a machine too busy
 * for simavr to keep up, the board runs late (its answers come late), but what it
 * receives, and when in its own time, is what the wire brings it: the line, asleep until
 * a byte comes, is woken at once, where one loop that also ran simavr would come round to
 * the pty tens of milliseconds late, and leave the wire idle meanwhile. */
#define SLICE (F_CPU / 1000) /* cycles simavr runs at a time when it is behind the clock */
#define QUEUE (1 << 20)      /* bytes taken from the pty and not yet read by the board */
#define RESET_EVENT (-1L)    /* in the queue: DTR rose, the board resets */
static struct {
  avr_cycle_count_t cycle;
  long baud; /* the wire's, for a byte; RESET_EVENT for a reset */
  uint8_t byte;
} queue[QUEUE];
static long queue_head, queue_tail; /* queue[head % QUEUE] .. queue[(tail - 1) % QUEUE] */
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER; /* the queue, origin, sim_cycle */
static double start;       /* the computer's clock when the harness began serving */
static long long origin;   /* the board's cycle at `start` (moved once: see take_open) */
static avr_cycle_count_t sim_cycle; /* how far the board has run (published by it) */

static avr_cycle_count_t clock_now(void) { /* the computer's clock, as a cycle */
  return (avr_cycle_count_t)(origin + (long long)((wall() - start) * F_CPU));
}
static double in_seconds(avr_cycle_count_t c) { /* a cycle in the log's seconds */
  return start + (double)((long long)c - origin) / F_CPU;
}

static void enqueue(avr_cycle_count_t cycle, long baud, uint8_t byte) {
  queue[queue_tail % QUEUE].cycle = cycle;
  queue[queue_tail % QUEUE].baud = baud;
  queue[queue_tail % QUEUE].byte = byte;
  queue_tail++;
}

/* --control: the commands read from stdin. */
static int control;
static char command[256];
static size_t command_len;
static struct {
  int pending, signum;
  pid_t pid;
  double at; /* in the log's seconds */
} order;

/* Read what came on stdin; a whole line is the next order (one at a time). */
static void read_commands(void) {
  ssize_t n = read(0, command + command_len, sizeof command - 1 - command_len);
  if (n <= 0) {
    if (n == 0) control = 0; /* stdin closed: no more commands */
    return;
  }
  command_len += (size_t)n;
  command[command_len] = 0;
  char *end;
  while ((end = strchr(command, '\n'))) {
    *end = 0;
    int signum, pid;
    double at = 0;
    int got = sscanf(command, "signal %d %d %lf", &signum, &pid, &at);
    if (got >= 2)
      order.pending = 1, order.signum = signum, order.pid = (pid_t)pid,
      order.at = got == 3 ? at : 0;
    else
      fprintf(stderr, "simboard: unknown command: %s\n", command);
    size_t rest = command_len - (size_t)(end + 1 - command);
    memmove(command, end + 1, rest + 1);
    command_len = rest;
  }
  if (command_len == sizeof command - 1) command_len = 0; /* no line fits: dropped */
}

/* The line's side of the pty: what it knows of the wire from the computer. */
static struct {
  int master;
  int hung_up, dtr, opened; /* nothing has the port open; DTR is down; never opened */
  avr_cycle_count_t free;   /* when the wire is free of the bytes taken */
  avr_cycle_count_t looked; /* when the pty was last looked at */
  int left;                 /* that look left bytes in the pty: the UART had no room */
  long taken, baud;         /* bytes taken; the wire's baud */
} line;

/* The board's thread: run it after the clock, a slice at a time when it is behind, each
 * queued byte (and reset) given to it when its time comes. */
static void *run_board(void *unused) {
  (void)unused;
  static struct { avr_cycle_count_t cycle; long baud; uint8_t byte; } due[4096];
  for (;;) {
    pthread_mutex_lock(&lock);
    if (!line.opened) { /* nobody has opened the port yet: see take_open */
      pthread_mutex_unlock(&lock);
      usleep(1000);
      continue;
    }
    avr_cycle_count_t now = clock_now(), target = avr->cycle + SLICE;
    if (target > now) target = now;
    long baud = queue_head == queue_tail ? line.baud : 0; /* the wire's, when idle */
    int n = 0;
    while (n < 4096 && queue_head < queue_tail && queue[queue_head % QUEUE].cycle <= target) {
      due[n].cycle = queue[queue_head % QUEUE].cycle;
      due[n].baud = queue[queue_head % QUEUE].baud;
      due[n++].byte = queue[queue_head % QUEUE].byte;
      queue_head++;
    }
    pthread_mutex_unlock(&lock);
    int r = 0;
    for (int k = 0; k < n && !r; k++) {
      if (due[k].baud == RESET_EVENT) {
        r = run_until(due[k].cycle);
        reset_board();
        wire_free = due[k].cycle;
        continue;
      }
      byte_cycles = (avr_cycle_count_t)(10 * F_CPU / (wire_baud = due[k].baud));
      r = send_byte(due[k].byte, due[k].cycle);
    }
    if (baud) { /* the computer reads the board's bytes at the baud it set (--bootloader) */
      wire_baud = baud;
      byte_cycles = (avr_cycle_count_t)(10 * F_CPU / baud);
    }
    if (!r) r = run_until(target);
    if (r < 0) exit(1);
    pthread_mutex_lock(&lock);
    sim_cycle = avr->cycle;
    int caught_up = avr->cycle >= clock_now();
    pthread_mutex_unlock(&lock);
    if (caught_up && n == 0) usleep(200);
  }
  return NULL;
}

/* Where the next byte taken would start on the wire at `now`: after the bytes taken
 * before it; bytes left in the pty at the last look had waited since then (the UART
 * took each as soon as it had room, however late this look came round); a byte that
 * came since, when it was looked at. Never where the board has already run. */
static avr_cycle_count_t next_start(avr_cycle_count_t now) {
  avr_cycle_count_t from = line.left ? line.looked : now;
  if (from < line.free) from = line.free;
  if (from < sim_cycle) from = sim_cycle;
  return from;
}

/* How many bytes the UART takes from the pty by `now` when the next would start at
 * `from`: one as each byte-time passes, and UART_AHEAD's worth beyond the wire. */
static long uart_room(avr_cycle_count_t now, avr_cycle_count_t from) {
  avr_cycle_count_t cycles = (avr_cycle_count_t)(10 * F_CPU / line.baud);
  long fifo = (long)(UART_AHEAD * F_CPU / cycles + 0.5);
  if (fifo < 1) fifo = 1;
  long long gap = (long long)now - (long long)from, b = (long long)cycles;
  long long whole = gap >= 0 ? gap / b : -((-gap + b - 1) / b); /* floor(gap / b) */
  long room = fifo + (long)whole, space = QUEUE - (queue_tail - queue_head) - 1;
  return room < space ? room : space;
}

/* A program opened the port (with the lock held): DTR rises, and an Uno resets on that
 * edge (after the bytes already on the wire, if any). The board is powered up then, as
 * the port is first opened, and reset at once (its reset flags say both): until then it
 * has not run (what it would have said would wait in the pty, where a serial port's
 * driver drops it, and simavr catching up would only make it answer late). */
static avr_cycle_count_t take_open(avr_cycle_count_t now) {
  line.hung_up = 0;
  if (!line.opened) { /* the board's thread has not run it: its cycle stands still */
    origin += (long long)avr->cycle - (long long)now;
    now = sim_cycle = line.free = line.looked = avr->cycle;
  }
  line.opened = 1;
  if (!line.dtr) {
    avr_cycle_count_t at = line.free > now ? line.free : now;
    enqueue(at, RESET_EVENT, 0);
    line.free = at;
  }
  line.dtr = 1;
  return now;
}

/* The program closed the port (its bytes all taken): DTR drops if it left HUPCL set. */
static void take_close(avr_cycle_count_t now) {
  if (!line.hung_up) {
    line.dtr = !hupcl(line.master);
    if (control) {
      printf("closed %.6f %ld\n", in_seconds(now), line.taken);
      fflush(stdout);
    }
  } else if (boot_path && line.dtr && hupcl(line.master))
    line.dtr = 0; /* a program opened and closed it unseen (stty), and left HUPCL set */
  line.hung_up = 1;
  line.left = 0;
}

/* Take what the pty holds that the UART has room for (with the lock held): each byte
 * placed on the wire, logged and queued for the board. */
static void take_bytes(const uint8_t *buf, ssize_t n, long room, avr_cycle_count_t now) {
  if (boot_path) { /* a real board's wire runs at the baud the program set */
    long baud = port_baud(line.master);
    if (baud) line.baud = baud;
  }
  avr_cycle_count_t from = next_start(now);
  avr_cycle_count_t cycles = (avr_cycle_count_t)(10 * F_CPU / line.baud);
  for (ssize_t k = 0; k < n; k++) {
    if (byte_log) fprintf(byte_log, "%.6f %d\n", in_seconds(from), buf[k]);
    enqueue(from, line.baud, buf[k]);
    from += cycles;
  }
  if (n > 0) {
    line.free = from;
    line.taken += n;
    if (byte_log) fflush(byte_log);
  }
  line.left = n > 0 && n == room;
  line.looked = now;
}

/* A signal ordered on stdin whose time has come (with the lock held): what the board
 * takes from now on starts on the wire after it. */
static void act(void) {
  if (!order.pending || in_seconds(clock_now()) < order.at) return;
  order.pending = 0;
  if (kill(order.pid, order.signum) < 0) perror("simboard: signal");
  avr_cycle_count_t sent = clock_now();
  if (line.looked < sent) line.looked = sent;
  printf("signalled %.6f %ld\n", in_seconds(sent), line.taken);
  fflush(stdout);
}

/* The line's thread: wait for bytes while the UART has room for them (what it has no
 * room for stays in the pty, where the program may still discard it: tcflush), take
 * them, notice an open and a close. */
static void serve_line(void) {
  for (;;) {
    pthread_mutex_lock(&lock);
    avr_cycle_count_t now = clock_now();
    long room = uart_room(now, next_start(now));
    /* ms: bytes, a close and an order wake it; an open does not, nor an order's time */
    int wait = order.pending || line.hung_up ? 1 : 100;
    pthread_mutex_unlock(&lock);
    if (room <= 0) { /* the UART is full: the pty is not looked at */
      usleep(200);
      continue;
    }
    struct pollfd p[2] = {{line.master, POLLIN, 0}, {0, POLLIN, 0}};
    poll(p, control ? 2 : 1, wait);
    if (control && (p[1].revents & (POLLIN | POLLHUP))) read_commands();
    pthread_mutex_lock(&lock);
    now = clock_now();
    room = uart_room(now, next_start(now));
    uint8_t buf[4096];
    if (room > (long)sizeof buf) room = sizeof buf;
    ssize_t n = (p[0].revents & POLLIN) && room > 0 ? read(line.master, buf, (size_t)room) : 0;
    int closed = n <= 0 && (p[0].revents & POLLHUP);
    if (closed)
      take_close(now);
    else { /* the port is open (a program that just opened it may not write at once) */
      if (line.hung_up) now = take_open(now);
      take_bytes(buf, n > 0 ? n : 0, room, now);
    }
    act();
    pthread_mutex_unlock(&lock);
    if (closed) usleep(10000); /* a hung-up pty polls at once: not in a loop */
  }
}

/* A real board runs on a chip of its own, whatever the computer's load: served in real
 * time, the simulated one asks for the CPU before the programs beside it (nice -15, where
 * allowed: as root, in CI; elsewhere it runs at the priority it was given). It takes only
 * what real time needs: caught up with the clock, both threads sleep. */
#define BOARD_NICE (-15)

static int serve(void) {
  int master, slave;
  if (setpriority(PRIO_PROCESS, 0, BOARD_NICE) < 0 && errno != EACCES && errno != EPERM)
    perror("simboard: setpriority"); /* (the threads made after this inherit it) */
  if (openpty(&master, &slave, NULL, NULL, NULL) < 0) {
    perror("simboard: openpty");
    return 1;
  }
  struct termios tio;
  tcgetattr(slave, &tio);
  cfmakeraw(&tio);
  if (boot_path) { /* a real board's port, as a serial driver sets up a device it finds */
    tio.c_cflag |= HUPCL;
    cfsetispeed(&tio, B9600);
    cfsetospeed(&tio, B9600);
  }
  tcsetattr(slave, TCSANOW, &tio);
  printf("%s\n", ttyname(slave));
  fflush(stdout);
  close(slave);
  fcntl(master, F_SETFL, O_NONBLOCK);
  if (control) fcntl(0, F_SETFL, O_NONBLOCK);
  pty_fd = master;
  line.master = master;
  line.hung_up = 1;
  line.baud = wire_baud;
  start = wall();
  origin = (long long)avr->cycle;
  sim_cycle = line.free = line.looked = avr->cycle;
  pthread_t board;
  if (pthread_create(&board, NULL, run_board, NULL) != 0) {
    perror("simboard: thread");
    return 1;
  }
  serve_line();
  return 0;
}

int main(int argc, char **argv) {
  const char *path = NULL;
  int pty = 0, bad = 0;
  long baud = 9600;
  double run_on = 0, wait = 0.05;
  for (int i = 1; i < argc; i++) {
    int more = i + 1 < argc;
    if (strcmp(argv[i], "--pty") == 0)
      pty = 1;
    else if (strcmp(argv[i], "--control") == 0)
      control = 1;
    else if (strcmp(argv[i], "--pulses") == 0)
      print_pulses = 1;
    else if (strcmp(argv[i], "--baud") == 0 && more)
      baud = atol(argv[++i]);
    else if (strcmp(argv[i], "--run-on") == 0 && more)
      run_on = atof(argv[++i]);
    else if (strcmp(argv[i], "--eeprom") == 0 && more)
      eeprom_path = argv[++i];
    else if (strcmp(argv[i], "--bootloader") == 0 && more)
      boot_path = argv[++i];
    else if (strcmp(argv[i], "--log") == 0 && more) {
      if (!(byte_log = fopen(argv[++i], "w"))) {
        perror("simboard: --log");
        return 2;
      }
    }
    else if (strcmp(argv[i], "--cut") == 0 && more)
      cut_after = atol(argv[++i]);
    else if (strcmp(argv[i], "--wait") == 0 && more)
      wait = atof(argv[++i]);
    else if (strcmp(argv[i], "--button") == 0 && more) {
      int pin = atoi(argv[++i]);
      if (pin < 0 || pin >= PINS) bad = 1;
      else button[pin] = 1;
    } else if (strcmp(argv[i], "--press") == 0 && i + 3 < argc && press_count < MAX_PRESSES) {
      presses[press_count].pin = atoi(argv[++i]);
      presses[press_count].at = atof(argv[++i]);
      presses[press_count].hold = atof(argv[++i]);
      int pin = presses[press_count++].pin;
      if (pin < 0 || pin >= PINS || !button[pin]) bad = 1; /* --button PIN first */
    } else if (strcmp(argv[i], "--watch") == 0 && more)
      watch_name = argv[++i];
    else if (strcmp(argv[i], "--flash") == 0 && i + 3 < argc && poke_count < MAX_POKES) {
      pokes[poke_count].name = argv[++i];
      pokes[poke_count].offset = (uint32_t)atol(argv[++i]);
      pokes[poke_count++].byte = (uint8_t)atoi(argv[++i]);
    }
    else if (!path && argv[i][0] != '-')
      path = argv[i];
    else
      bad = 1;
  }
  if (!path || bad || baud <= 0 || run_on < 0 || wait < 0) {
    fprintf(stderr, "usage: simboard FIRMWARE.elf [--baud B] [--run-on S] [--eeprom FILE] "
                    "[--cut N] [--pulses] [--wait S] [--button PIN [--press PIN S H]...] "
                    "[--watch SYMBOL] [--flash SYMBOL K B] [--bootloader HEX] < timed\n"
                    "       simboard FIRMWARE.elf --pty [--baud B] [--eeprom FILE] [--log LOG] "
                    "[--bootloader HEX] [--control]\n");
    return 2;
  }
  elf_firmware_t fw;
  if (load(path, &fw) < 0) return 1;
  byte_cycles = (avr_cycle_count_t)(10 * F_CPU / baud);
  wire_baud = baud;
  return pty ? serve() : script(run_on, wait);
}
