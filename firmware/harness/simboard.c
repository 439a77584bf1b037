/* simboard: a built board image (ATmega328P, 16 MHz) running in simavr, fed bytes on
 * its serial port (UART0) at a real link's pace.
 *
 *   simboard FIRMWARE.elf [--baud B] < timed
 *       Waits for the board's first WAIT, then sends each "<seconds> <byte>" line of the
 *       input (gestc compile --format timed) at its time, counted from that WAIT, one
 *       byte-time apart at least; then asks for a DUMP. Prints, one per line:
 *         ready S                  when the first WAIT came (s of simulated time)
 *         out S BYTE               every byte the board sent (s after ready)
 *         sent N / read N          bytes sent to the board / bytes its sketch read
 *         jumps N                  servos attached before a value was written to them
 *         dump BOARD N ID V ...    the board's answer to the final DUMP
 *   simboard FIRMWARE.elf --pty [--baud B]
 *       Serves the board on a pseudo-terminal in real time and prints its path; like an
 *       Uno or a Nano, the board resets when a program opens the port.
 *
 * Bytes the board reads are counted by the sketch (inmoov_rx_count), and the Servo
 * stand-in counts jumps (servo_stub_jumps); both are read from the image's RAM.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <simavr/avr_uart.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>

#define F_CPU 16000000ULL
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
static uint32_t rx_addr, jumps_addr;   /* RAM addresses of the two counters, 0 if absent */
static int xoff;                       /* simavr's UART cannot take another byte yet */

/* simavr's own messages: errors to stderr, the rest (loading, tracing) dropped, so that
 * stdout carries only what this harness prints. */
static void logger(avr_t *a, const int level, const char *format, va_list ap) {
  (void)a;
  if (level <= LOG_ERROR) vfprintf(stderr, format, ap);
}

static double seconds(avr_cycle_count_t c) { return (double)c / F_CPU; }

static void on_output(struct avr_irq_t *irq, uint32_t value, void *param) {
  (void)irq;
  (void)param;
  if (!ready_at && value == 254) ready_at = avr->cycle;
  if (pty_fd >= 0) {
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

/* Run the board until `cycle`. */
static int run_until(avr_cycle_count_t cycle) {
  while (avr->cycle < cycle) {
    int state = avr_run(avr);
    if (state == cpu_Done || state == cpu_Crashed) {
      fprintf(stderr, "simboard: the board stopped (%s)\n",
              state == cpu_Done ? "done" : "crashed");
      return -1;
    }
  }
  return 0;
}

/* Put one byte on the wire: it reaches the UART no sooner than a byte-time after the
 * previous one (simavr adds the byte's own transmission time), and not while simavr's
 * UART still holds bytes it has not delivered (its own byte-time is a little longer
 * than the nominal one). What the board's sketch does with them is what is tested. */
static int send_byte(uint8_t byte, avr_cycle_count_t at) {
  if (at < wire_free) at = wire_free;
  if (run_until(at) < 0) return -1;
  while (xoff) {
    if (run_until(avr->cycle + 100) < 0) return -1;
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

static int load(const char *path, elf_firmware_t *fw) {
  avr_global_logger_set(logger);
  memset(fw, 0, sizeof *fw);
  if (elf_read_firmware(path, fw) != 0) {
    fprintf(stderr, "simboard: cannot read %s\n", path);
    return -1;
  }
  avr = avr_make_mcu_by_name("atmega328p");
  if (!avr) return -1;
  avr_init(avr);
  avr->log = 0;
  avr_load_firmware(avr, fw);
  avr->frequency = F_CPU;
  uint32_t flags = 0;
  avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
  flags &= ~AVR_UART_FLAG_STDIO;
  avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
  uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
                          on_output, NULL);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF),
                          on_xoff, NULL);
  avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON),
                          on_xon, NULL);
  rx_addr = find_symbol(fw, "inmoov_rx_count");
  jumps_addr = find_symbol(fw, "servo_stub_jumps");
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

static int script(void) {
  if (wait_ready() < 0) return 1;
  long sent = 0;
  double t;
  int byte;
  avr_cycle_count_t last = ready_at;
  while (scanf("%lf %d", &t, &byte) == 2) {
    if (byte < 0 || byte > 255 || t < 0) {
      fprintf(stderr, "simboard: bad line: %f %d\n", t, byte);
      return 1;
    }
    last = ready_at + (avr_cycle_count_t)(t * F_CPU + 0.5);
    if (send_byte((uint8_t)byte, last) < 0) return 1;
    sent++;
  }
  /* the stream is over: let it settle, then ask for the board's values */
  long before_dump = out_count;
  if (send_byte(253, last + F_CPU / 20) < 0) return 1;
  sent++;
  avr_cycle_count_t limit = avr->cycle + F_CPU / 5;
  int ended = 0;
  while (!ended && avr->cycle < limit) {
    if (run_until(avr->cycle + 1000) < 0) return 1;
    for (long k = before_dump; k < out_count && !ended; k++) ended = out[k].byte == 251;
  }
  if (run_until(avr->cycle + byte_cycles * 4) < 0) return 1;
  printf("ready %.6f\n", seconds(ready_at));
  for (long k = 0; k < out_count; k++)
    printf("out %.6f %d\n", seconds(out[k].cycle - ready_at), out[k].byte);
  printf("sent %ld\nread %u\njumps %u\n", sent, read_u16(rx_addr),
         jumps_addr ? avr->data[jumps_addr] : 0);
  for (long k = before_dump; k < out_count; k++) {
    if (out[k].byte != 252 || k + 2 >= out_count) continue;
    int n = out[k + 2].byte;
    if (k + 3 + 2 * n >= out_count || out[k + 3 + 2 * n].byte != 251) continue;
    printf("dump %d %d", out[k + 1].byte, n);
    for (int i = 0; i < 2 * n; i++) printf(" %d", out[k + 3 + i].byte);
    printf("\n");
    break;
  }
  return 0;
}

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec / 1e9;
}

static int serve(void) {
  int master, slave;
  if (openpty(&master, &slave, NULL, NULL, NULL) < 0) {
    perror("simboard: openpty");
    return 1;
  }
  struct termios tio;
  tcgetattr(slave, &tio);
  cfmakeraw(&tio);
  tcsetattr(slave, TCSANOW, &tio);
  printf("%s\n", ttyname(slave));
  fflush(stdout);
  close(slave);
  fcntl(master, F_SETFL, O_NONBLOCK);
  pty_fd = master;
  int hung_up = 1;
  double start = wall();
  avr_cycle_count_t origin = avr->cycle;
  for (;;) {
    struct pollfd p = {master, POLLIN, 0};
    poll(&p, 1, 1);
    avr_cycle_count_t now = origin + (avr_cycle_count_t)((wall() - start) * F_CPU);
    uint8_t buf[256];
    ssize_t n = (p.revents & POLLIN) ? read(master, buf, sizeof buf) : 0;
    if (n <= 0 && (p.revents & POLLHUP)) {
      hung_up = 1;
      if (run_until(now) < 0) return 1;
      usleep(10000);
      continue;
    }
    if (hung_up) { /* a program opened the port: the board resets, as an Uno does */
      hung_up = 0;
      avr_reset(avr);
      ready_at = 0;
      wire_free = now;
    }
    for (ssize_t k = 0; k < n; k++) {
      if (send_byte(buf[k], now) < 0) return 1;
    }
    if (run_until(now) < 0) return 1;
  }
}

int main(int argc, char **argv) {
  const char *path = NULL;
  int pty = 0;
  long baud = 9600;
  for (int i = 1; i < argc; i++) {
    if (strcmp(argv[i], "--pty") == 0)
      pty = 1;
    else if (strcmp(argv[i], "--baud") == 0 && i + 1 < argc)
      baud = atol(argv[++i]);
    else if (!path)
      path = argv[i];
    else
      path = NULL, i = argc;
  }
  if (!path || baud <= 0) {
    fprintf(stderr, "usage: simboard FIRMWARE.elf [--baud B] < timed\n"
                    "       simboard FIRMWARE.elf --pty [--baud B]\n");
    return 2;
  }
  elf_firmware_t fw;
  if (load(path, &fw) < 0) return 1;
  byte_cycles = (avr_cycle_count_t)(10 * F_CPU / baud);
  return pty ? serve() : script();
}
