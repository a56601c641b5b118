/* The navigation computer's replay on the Cortex-M7 from C: what a C flight image does with
 * nav.h. Reads the replay input `replay-in.bin` (a nav-sim scenario's setup, then its sensor
 * log) through semihosting, configures the computer from the C structs the setup gives, runs
 * each frame in a 2 ms SysTick frame (500 Hz of QEMU's virtual time), measures what
 * `nav_run_frame` costs in instructions (`-icount shift=0`: one instruction per ns) exactly
 * as the Rust firmware measures its frame (qemu/src/frame_clock.rs), and writes per frame the
 * output record and the cost to `replay-out.bin` and the stack figures to
 * `replay-stack.bin`: the files of the Rust replay firmware (qemu/src/bin/replay.rs), so the
 * two compare bit for bit. Prints `C-REPLAY frames=... worst=... overruns=...`. */
#include <stdint.h>

#include "nav.h"
#include "semihosting.h"
#include "startup.h"

/* SysTick ticks per 2 ms frame at the MPS2 system clock of 25 MHz. */
#define FRAME_TICKS 50000u
/* Instructions per SysTick tick under -icount shift=0 (1 GHz virtual / 25 MHz). */
#define INSTRUCTIONS_PER_TICK 40u
/* Frame budget in instructions (2 ms). */
#define FRAME_BUDGET_INSTRUCTIONS 2000000u
/* Frames buffered per write. */
#define FRAMES_PER_WRITE 16
/* Words per output frame: the record and the cost. */
#define FRAME_WORDS (NAV_OUTPUT_WORDS + 1)

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

static uint64_t computer[NAV_COMPUTER_MAX_BYTES / 8];
static uint64_t replay[NAV_REPLAY_MAX_BYTES / 8];
static uint64_t out_words[FRAME_WORDS * FRAMES_PER_WRITE];

/* Frame interrupts since the clock started. */
static volatile uint32_t frame_ticks_elapsed;
static uint32_t frames_started;
/* The dearest frame so far and the frames beyond the budget (instructions). */
static uint32_t worst_cost;
static uint32_t overruns;

void SysTick_Handler(void) { frame_ticks_elapsed++; }

static void start_frame_clock(void) {
  SYST_RVR = FRAME_TICKS - 1;
  SYST_CVR = 0;
  /* Processor clock, interrupt, enable. */
  SYST_CSR = 4u | 2u | 1u;
  frames_started = frame_ticks_elapsed;
}

/* Ticks into the SysTick period of a counter value (it counts down to 0, then reloads). */
static uint32_t into_period(uint32_t current) { return (FRAME_TICKS - current) % FRAME_TICKS; }

/* Waits for the next frame interrupt, runs the frame and returns its cost (instructions). */
static uint32_t run_frame(const NavFrameInputs *inputs, NavTelemetry *telemetry,
                          NavStatus *status) {
  while (frame_ticks_elapsed <= frames_started) __asm__ volatile("wfi");
  frames_started = frame_ticks_elapsed;
  uint32_t start_current = SYST_CVR;
  *status = nav_run_frame(computer, inputs, telemetry, 0);
  uint32_t end_current = SYST_CVR;
  uint32_t ticks_passed = frame_ticks_elapsed - frames_started;
  uint32_t start_position = into_period(start_current);
  uint32_t elapsed = ticks_passed * FRAME_TICKS + into_period(end_current);
  /* Wrapped between the last read and the interrupt being taken. */
  if (elapsed < start_position) elapsed += FRAME_TICKS;
  elapsed -= start_position;
  frames_started += ticks_passed;
  return elapsed * INSTRUCTIONS_PER_TICK;
}

static void print_number(const char *label, uint32_t value) {
  char text[16];
  int position = 15;
  text[position] = '\0';
  do {
    text[--position] = (char)('0' + value % 10);
    value /= 10;
  } while (value != 0 && position > 0);
  host_print(label);
  host_print(&text[position]);
}

/* Reads the setup and the log header and configures the computer; 0 on success. */
static int start(int input) {
  static uint8_t bytes[NAV_REPLAY_START_BYTES];
  NavConfig config;
  NavGroundConstants ground;
  NavInitialState initial;
  NavFault fault;
  if (host_read(input, bytes, sizeof bytes) != sizeof bytes) return 1;
  if (nav_replay_start(replay, sizeof replay, bytes, sizeof bytes, &config, &ground, &initial,
                       &fault) != NAV_STATUS_OK) {
    return 1;
  }
  if (nav_configure(computer, sizeof computer, &config, &ground, &initial, &fault) !=
      NAV_STATUS_OK) {
    print_number("configuration refused, parameter ", fault.param);
    host_print("\n");
    return 1;
  }
  return nav_set_frame_budget(computer, FRAME_BUDGET_INSTRUCTIONS) != NAV_STATUS_OK;
}

/* The next frame's inputs from the log: 1 when a frame is ready, 0 at the end, -1 on a
 * refused record. */
static int next_frame(int input, NavFrameInputs *inputs) {
  static uint8_t record[NAV_LOG_RECORD_BYTES];
  static int finished;
  uint8_t ready = 0;
  for (;;) {
    if (nav_replay_next_frame(replay, inputs, &ready) != NAV_STATUS_OK) return -1;
    if (ready) return 1;
    if (finished) return 0;
    if (host_read(input, record, sizeof record) != sizeof record) {
      finished = 1;
      if (nav_replay_finish(replay) != NAV_STATUS_OK) return -1;
    } else if (nav_replay_push(replay, record, 0) != NAV_STATUS_OK) {
      return -1;
    }
  }
}

/* Stores the frame's record and cost; writes the buffer when full (or `flush`). */
static int store(int output, const NavTelemetry *telemetry, uint32_t cost, int flush) {
  static int buffered;
  if (telemetry) {
    NavReportedStates states;
    uint64_t *slot = &out_words[buffered * FRAME_WORDS];
    if (nav_reported_states(computer, &states) != NAV_STATUS_OK ||
        nav_replay_output_record(replay, telemetry, &states, slot) != NAV_STATUS_OK) {
      return 1;
    }
    slot[NAV_OUTPUT_WORDS] = cost;
    buffered++;
  }
  if (buffered == FRAMES_PER_WRITE || (flush && buffered > 0)) {
    /* Little-endian words: the Cortex-M7's byte order is the file's. */
    if (host_write(output, out_words, (size_t)buffered * FRAME_WORDS * 8) != 0) return 1;
    buffered = 0;
  }
  return 0;
}

static int write_stack(StackUsage loop, StackUsage start_up) {
  uint64_t words[3] = {loop.high_water_bytes, loop.region_bytes, start_up.high_water_bytes};
  int file = host_open("replay-stack.bin", 1);
  if (file < 0) return 1;
  int failed = host_write(file, words, sizeof words);
  host_close(file);
  return failed;
}

/* Replays the log frame by frame; the frames, or -1. */
static long replay_log(int input, int output) {
  static NavFrameInputs inputs;
  static NavTelemetry telemetry;
  long frames = 0;
  int more;
  start_frame_clock();
  while ((more = next_frame(input, &inputs)) == 1) {
    NavStatus status;
    uint32_t cost = run_frame(&inputs, &telemetry, &status);
    if (status != NAV_STATUS_OK || nav_report_frame_cost(computer, cost) != NAV_STATUS_OK) {
      return -1;
    }
    if (store(output, &telemetry, cost, 0) != 0) return -1;
    if (cost > worst_cost) worst_cost = cost;
    if (cost > FRAME_BUDGET_INSTRUCTIONS) overruns++;
    frames++;
  }
  if (more < 0 || store(output, 0, 0, 1) != 0) return -1;
  return frames;
}

int main(void) {
  int input = host_open("replay-in.bin", 0);
  int output = host_open("replay-out.bin", 1);
  if (input < 0 || output < 0 || start(input) != 0) {
    host_print("C-REPLAY: cannot start\n");
    return 1;
  }
  StackUsage start_up = stack_usage();
  repaint_below_stack_pointer();
  long frames = replay_log(input, output);
  host_close(output);
  host_close(input);
  StackUsage loop = stack_usage();
  if (frames <= 0 || write_stack(loop, start_up) != 0) {
    host_print("C-REPLAY: failed\n");
    return 1;
  }
  print_number("C-REPLAY frames=", (uint32_t)frames);
  print_number(" worst=", worst_cost);
  print_number(" overruns=", overruns);
  print_number(" stack=", loop.high_water_bytes);
  print_number(" start-up stack=", start_up.high_water_bytes);
  host_print("\n");
  return overruns != 0;
}
