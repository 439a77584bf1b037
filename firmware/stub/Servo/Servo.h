// A stand-in for the Arduino Servo library, with its interface, for builds on a machine
// without it (Debian ships none). It keeps each servo's pulse width and pin, and drives
// nothing; the Arduino IDE builds with the real <Servo.h> instead.
#ifndef Servo_h
#define Servo_h

#include <inttypes.h>

#define MIN_PULSE_WIDTH 544      // us, angle 0
#define MAX_PULSE_WIDTH 2400     // us, angle 180
#define DEFAULT_PULSE_WIDTH 1500  // us, what attach() starts at if nothing was written
#define MAX_SERVOS 12
#define INVALID_SERVO 255

class Servo {
 public:
  Servo();
  uint8_t attach(int pin);
  uint8_t attach(int pin, int min, int max);
  void detach();
  void write(int value);  // an angle (0..180), or a pulse width in us if 544 or more
  void writeMicroseconds(int value);
  int read();
  int readMicroseconds();
  bool attached();

 private:
  uint8_t index_;
  int16_t min_;
  int16_t max_;
  bool written_;
};

// What the stand-in knows of every servo (the simulator harness may read these).
extern uint16_t servo_stub_pulse[MAX_SERVOS];  // us
extern int8_t servo_stub_pin[MAX_SERVOS];      // -1: not attached
extern uint8_t servo_stub_jumps;  // servos attached before anything was written to them

#endif
