// The protocol cores on this computer, driven by the tests (tests/test_firmware.py).
//
//   core_driver servo < script     a servo board: "board ID", "servo ID PIN LO HI REV REST"
//                                  lines, then "begin [V V ...]" (from the rest values or
//                                  this pose: prints each servo's index, angle and pulse
//                                  in us), or "case B B B ..." lines: each case
//                                  starts from the boot state and prints
//                                  "writes ID VALUE ANGLE ... | out B B ... | relaxed R"
//   core_driver fuzz N SEED < script   N random bytes into that board: every write in
//                                  range and owned, back in step after CANCEL; "ok"
//   core_driver store < script     a servo board's stored pose on an EEPROM array: "board"
//                                  and "servo" lines as above, then "eeprom SIZE" (a fresh
//                                  one, all 0xFF), "fill B", "boot" (a reset: prints "boot
//                                  none" or "boot V V ... seq Q"), "write MS V V ..." (the
//                                  servos are written these values), "run MS" (the loop
//                                  runs every ms until then; a byte written keeps the
//                                  EEPROM busy 4 ms), "cut N" (the power fails after N
//                                  more bytes are written), "wear" (prints "wear BYTES MAX":
//                                  bytes written, the most writes of one cell)
//   core_driver stored < script    a servo board with stored gestures: "board" and
//                                  "servo" lines as above, "blob HEX" (the stored bytes),
//                                  "begin V V ..." (a board holding this pose), "host T B
//                                  B ..." (bytes from the host at T us: prints "reply B
//                                  ..." for what the core and the catalog send), "run T"
//                                  (the player until T us, a servo frame ending every 20 ms
//                                  from 10 ms: prints "write T INDEX VALUE", "end T")
//   core_driver glove < script     a glove: "deadband D", "sensor ID PIN LO HI REV" lines,
//                                  then "read R R ..." (sensor readings: prints the bytes
//                                  sent) and "host B" (a byte from the computer) lines
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glove_core.h"
#include "pose_store.h"
#include "servo_core.h"
#include "stored_player.h"

using inmoov::FlexSettings;
using inmoov::GloveCore;
using inmoov::PoseStore;
using inmoov::ServoCore;
using inmoov::ServoSettings;
using inmoov::StoredPlayer;

static char writes[8192];
static char out[8192];
static uint8_t last_index, last_angle;
static int write_count;

static void append(char* buf, int value) {
  size_t n = strlen(buf);
  snprintf(buf + n, 8192 - n, " %d", value);
}

static void on_write(uint8_t index, uint8_t angle) {
  last_index = index;
  last_angle = angle;
  write_count++;
  append(writes, index);  // replaced by the ID below
  append(writes, angle);
}

static void on_send(uint8_t byte) { append(out, byte); }

static int driving = 1;
static void on_drive(bool on) { driving = on; }

static int next_int(char** p) { return static_cast<int>(strtol(*p, p, 10)); }

// A "board ID" or "servo ID PIN LO HI REV REST" line: read into `board` or `servos[*n]`.
static bool board_line(const char* line, int* board, ServoSettings* servos, int* n) {
  char* p = const_cast<char*>(line) + 5;
  if (strncmp(line, "board", 5) == 0) {
    *board = next_int(&p);
  } else if (strncmp(line, "servo", 5) == 0) {
    ServoSettings& s = servos[(*n)++];
    s.id = static_cast<uint8_t>(next_int(&p));
    s.pin = static_cast<uint8_t>(next_int(&p));
    s.lo = static_cast<uint8_t>(next_int(&p));
    s.hi = static_cast<uint8_t>(next_int(&p));
    s.reversed = static_cast<uint8_t>(next_int(&p));
    s.rest = static_cast<uint8_t>(next_int(&p));
  } else {
    return false;
  }
  return true;
}

static int servo(bool fuzz, long count, unsigned seed) {
  ServoSettings servos[64];
  uint8_t values[64];
  int board = 181, n = 0;
  char line[8192];
  while (fgets(line, sizeof line, stdin)) {
    char* p = line;
    if (board_line(line, &board, servos, &n)) continue;
    if (strncmp(line, "begin", 5) == 0 || strncmp(line, "case", 4) == 0) {
      ServoCore core(static_cast<uint8_t>(board), servos, static_cast<uint8_t>(n), values,
                     on_write, on_send, on_drive);
      writes[0] = out[0] = 0;
      driving = 1;
      if (line[0] == 'b') {  // "begin [V V ...]": from the rest values, or from this pose
        p += 5;
        uint8_t pose[64];
        int k = 0;
        for (char* end; k < n; k++, p = end) {
          pose[k] = static_cast<uint8_t>(strtol(p, &end, 10));
          if (end == p) break;
        }
        core.begin(k == n && n > 0 ? pose : 0);
        printf("begin");
        for (int i = 0; i < n; i++) {
          uint8_t angle = core.angle(static_cast<uint8_t>(i), core.value(static_cast<uint8_t>(i)));
          printf(" %d %d %d", i, angle, inmoov::pulse_us(angle));
        }
        printf("\n");
        continue;
      }
      core.begin();
      writes[0] = 0;
      p += 4;
      // a write is reported as ID VALUE ANGLE: the core gives the index and the angle
      char report[8192] = "";
      for (;;) {
        char* end;
        long byte = strtol(p, &end, 10);
        if (end == p) break;
        p = end;
        write_count = 0;
        core.feed(static_cast<uint8_t>(byte));
        if (write_count) {
          size_t k = strlen(report);
          snprintf(report + k, sizeof report - k, " %d %d %d", servos[last_index].id,
                   core.value(last_index), last_angle);
        }
      }
      if (driving == core.relaxed()) {
        printf("relaxed %d but the pulses are %s\n", core.relaxed(), driving ? "on" : "off");
        return 1;
      }
      printf("writes%s | out%s | relaxed %d\n", report, out, core.relaxed());
    }
  }
  if (!fuzz) return 0;
  ServoCore core(static_cast<uint8_t>(board), servos, static_cast<uint8_t>(n), values,
                 on_write, on_send, on_drive);
  core.begin();
  srand(seed);
  for (long k = 0; k < count; k++) {
    write_count = 0;
    writes[0] = out[0] = 0;
    core.feed(static_cast<uint8_t>(rand() & 0xFF));
    if (write_count) {
      const ServoSettings& s = servos[last_index];
      uint8_t lo = s.lo, hi = s.hi;
      if (last_index >= n || core.value(last_index) > 180 || last_angle < lo || last_angle > hi) {
        printf("bad write after %ld bytes: servo index %d value %d angle %d\n", k, last_index,
               core.value(last_index), last_angle);
        return 1;
      }
    }
    if (rand() % 50 == 0) {  // back in step after a CANCEL, whatever came before
      core.feed(inmoov::CANCEL);
      write_count = 0;
      core.feed(servos[0].id);
      core.feed(77);
      if (write_count != 1 || last_index != 0 || core.value(0) != 77) {
        printf("out of step after a CANCEL at byte %ld\n", k);
        return 1;
      }
    }
  }
  printf("ok %ld bytes\n", count);
  return 0;
}

// -- the stored pose ------------------------------------------------------------------
static uint8_t eeprom[4096];
static long cell_writes[4096];
static long eeprom_size = 1024, busy_until = 0, clock_ms = 0, cut_left = -1;

static uint8_t eeprom_read(uint16_t address) {
  if (address >= eeprom_size) {
    printf("read outside the EEPROM: %u\n", address);
    exit(1);
  }
  return eeprom[address];
}

static bool eeprom_write(uint16_t address, uint8_t byte) {
  if (address >= eeprom_size) {
    printf("write outside the EEPROM: %u\n", address);
    exit(1);
  }
  if (clock_ms < busy_until) return false;
  if (cut_left == 0 || eeprom[address] == byte) return true;  // powered off / unchanged
  eeprom[address] = byte;
  cell_writes[address]++;
  busy_until = clock_ms + 4;
  if (cut_left > 0) cut_left--;
  return true;
}

static int store() {
  ServoSettings servos[64];
  uint8_t values[64], record[64 + PoseStore::OVERHEAD];
  int board = 181, n = 0;
  PoseStore* store = 0;
  memset(eeprom, 0xFF, sizeof eeprom);
  char line[8192];
  while (fgets(line, sizeof line, stdin)) {
    char* p = line;
    if (board_line(line, &board, servos, &n)) continue;
    if (strncmp(line, "eeprom", 6) == 0) {
      p += 6;
      eeprom_size = next_int(&p);
      memset(eeprom, 0xFF, sizeof eeprom);
      memset(cell_writes, 0, sizeof cell_writes);
    } else if (strncmp(line, "fill", 4) == 0) {
      p += 4;
      memset(eeprom, next_int(&p), sizeof eeprom);
    } else if (strncmp(line, "boot", 4) == 0) {
      delete store;
      store = new PoseStore(static_cast<uint16_t>(eeprom_size), static_cast<uint8_t>(board),
                            servos, static_cast<uint8_t>(n), record, eeprom_read, eeprom_write);
      cut_left = -1;
      if (!store->load(values)) {
        printf("boot none\n");
        continue;
      }
      printf("boot");
      for (int i = 0; i < n; i++) printf(" %d", values[i]);
      printf(" seq %u\n", store->seq());
    } else if (strncmp(line, "write", 5) == 0) {
      p += 5;
      clock_ms = next_int(&p);
      for (int i = 0; i < n; i++) values[i] = static_cast<uint8_t>(next_int(&p));
      store->changed(static_cast<uint16_t>(clock_ms));
    } else if (strncmp(line, "run", 3) == 0) {
      p += 3;
      long until = next_int(&p);
      for (; clock_ms <= until; clock_ms++) store->poll(static_cast<uint16_t>(clock_ms), values);
      clock_ms = until;
    } else if (strncmp(line, "cut", 3) == 0) {
      p += 3;
      cut_left = next_int(&p);
    } else if (strncmp(line, "wear", 4) == 0) {
      long total = 0, most = 0;
      for (long a = 0; a < eeprom_size; a++) {
        total += cell_writes[a];
        if (cell_writes[a] > most) most = cell_writes[a];
      }
      printf("wear %ld %ld\n", total, most);
    }
  }
  delete store;
  return 0;
}

// -- stored gestures -------------------------------------------------------------------
static uint8_t blob[65536];
static long now_us = 0;
static ServoCore* stored_core = 0;

static uint8_t blob_read(uint16_t address) { return blob[address]; }

static void stored_write(uint8_t index, uint8_t angle) {
  (void)angle;
  printf("write %ld %d %d\n", now_us, index, stored_core->value(index));
}

static int stored() {
  ServoSettings servos[16];
  uint8_t values[16], next[16];
  uint16_t positions[16], speeds[16];
  int board = 181, n = 0;
  char line[200000];
  StoredPlayer* player = 0;
  while (fgets(line, sizeof line, stdin)) {
    char* p = line;
    if (board_line(line, &board, servos, &n)) continue;
    if (strncmp(line, "blob", 4) == 0) {
      p += 4;
      while (*p == ' ') p++;
      for (int k = 0; p[0] && p[1] && p[0] != '\n'; k++, p += 2) {
        char hex[3] = {p[0], p[1], 0};
        blob[k] = static_cast<uint8_t>(strtol(hex, 0, 16));
      }
    } else if (strncmp(line, "begin", 5) == 0) {
      p += 5;
      uint8_t pose[16];
      for (int i = 0; i < n; i++) pose[i] = static_cast<uint8_t>(next_int(&p));
      delete stored_core;
      delete player;
      stored_core = new ServoCore(static_cast<uint8_t>(board), servos, static_cast<uint8_t>(n),
                                  values, stored_write, on_send, on_drive);
      stored_core->begin(pose);
      player = new StoredPlayer(static_cast<uint8_t>(board), blob_read, stored_core, positions,
                                speeds, next);
      now_us = 0;
    } else if (strncmp(line, "host", 4) == 0) {
      p += 4;
      now_us = next_int(&p);
      out[0] = 0;
      for (char* end;; p = end) {
        long byte = strtol(p, &end, 10);
        if (end == p) break;
        player->heard(static_cast<uint8_t>(byte), stored_core->expects_id(),
                      static_cast<uint32_t>(now_us));
        stored_core->feed(static_cast<uint8_t>(byte));
      }
      for (int16_t b; (b = player->reply()) >= 0;) append(out, b);
      printf("reply%s\n", out);
    } else if (strncmp(line, "run", 3) == 0) {
      p += 3;
      long until = next_int(&p);
      for (; now_us <= until; now_us += 4) {
        uint8_t frames = static_cast<uint8_t>((now_us + 10000) / 20000);
        if (player->poll(static_cast<uint32_t>(now_us), frames)) printf("end %ld\n", now_us);
      }
      now_us = until;
    }
  }
  delete player;
  delete stored_core;
  return 0;
}

static int glove() {
  FlexSettings sensors[16];
  uint16_t bounds[32], readings[16] = {0};
  uint8_t sent[16];
  int n = 0, deadband = 2;
  char line[8192];
  GloveCore* core = 0;
  while (fgets(line, sizeof line, stdin)) {
    char* p = line;
    if (strncmp(line, "deadband", 8) == 0) {
      p += 8;
      deadband = next_int(&p);
    } else if (strncmp(line, "sensor", 6) == 0) {
      p += 6;
      FlexSettings s;
      s.servo_id = static_cast<uint8_t>(next_int(&p));
      s.pin = static_cast<uint8_t>(next_int(&p));
      s.lo = static_cast<uint16_t>(next_int(&p));
      s.hi = static_cast<uint16_t>(next_int(&p));
      s.reversed = static_cast<uint8_t>(next_int(&p));
      sensors[n++] = s;
    } else {
      if (!core) {
        core = new GloveCore(sensors, static_cast<uint8_t>(n), static_cast<uint8_t>(deadband),
                             bounds, sent, on_send);
        core->begin();
      }
      out[0] = 0;
      if (strncmp(line, "read", 4) == 0) {
        p += 4;
        for (int i = 0; i < n; i++) readings[i] = static_cast<uint16_t>(next_int(&p));
        core->update(readings);
      } else if (strncmp(line, "host", 4) == 0) {
        p += 4;
        core->feed(static_cast<uint8_t>(next_int(&p)), readings);
      }
      printf("sent%s\n", out);
    }
  }
  delete core;
  return 0;
}

int main(int argc, char** argv) {
  if (argc >= 2 && strcmp(argv[1], "servo") == 0) return servo(false, 0, 0);
  if (argc >= 4 && strcmp(argv[1], "fuzz") == 0)
    return servo(true, atol(argv[2]), static_cast<unsigned>(atol(argv[3])));
  if (argc >= 2 && strcmp(argv[1], "glove") == 0) return glove();
  if (argc >= 2 && strcmp(argv[1], "store") == 0) return store();
  if (argc >= 2 && strcmp(argv[1], "stored") == 0) return stored();
  fprintf(stderr, "usage: core_driver servo | fuzz N SEED | glove | store | stored  (script "
                  "on stdin)\n");
  return 2;
}
