/* A C team's regression test around the navigation computer (nav.h): replays a sensor log
 * that nav-sim wrote (the replay input: the scenario's setup, then the binary log;
 * docs/guide/replay-format.md) frame by frame through the C interface, and writes each frame's
 * output record, as the Rust replay does, so the two compare bit for bit.
 *
 *   main REPLAY-IN REPLAY-OUT
 *
 * REPLAY-OUT holds, per frame, NAV_OUTPUT_WORDS little-endian 64-bit words and one word of
 * frame cost (0 here: the host measures none). The last line printed is the final frame's
 * navigation and health. Exit status 0 when the whole log was replayed.
 *
 * Build, from the repository root after `cargo build -p nav-c --release`:
 *   cc -std=c99 -O2 -I nav-c/include examples/c-host/main.c target/release/libnav_c.a \
 *     -lpthread -lm -ldl -o nav-replay */
#include <stdint.h>
#include <stdio.h>

#include "nav.h"

/* The computer's and the replay's memory: static, as in a flight image. */
static uint64_t computer[NAV_COMPUTER_MAX_BYTES / 8];
static uint64_t replay[NAV_REPLAY_MAX_BYTES / 8];

/* Prints a refusal with the parameter or input it concerns. */
static int refused(const char *call, NavStatus status, const NavFault *fault) {
  const char *param = nav_param_path(fault->param);
  fprintf(stderr, "%s: status %d, argument %d, field %d, parameter %s, input %d\n", call,
          (int)status, (int)fault->argument, (int)fault->field, param ? param : "-",
          (int)fault->input);
  return 1;
}

/* Writes one frame's record and its cost word, little-endian (the host's byte order). */
static int write_record(FILE *out, const NavTelemetry *telemetry) {
  static uint64_t words[NAV_OUTPUT_WORDS + 1];
  NavReportedStates states;
  if (nav_reported_states(computer, &states) != NAV_STATUS_OK ||
      nav_replay_output_record(replay, telemetry, &states, words) != NAV_STATUS_OK) {
    return 1;
  }
  words[NAV_OUTPUT_WORDS] = 0;
  return fwrite(words, sizeof words, 1, out) != 1;
}

/* Replays the records of `in` through the computer; the number of frames, or -1. */
static long replay_log(FILE *in, FILE *out, NavTelemetry *telemetry) {
  NavFrameInputs inputs;
  NavFault fault;
  uint8_t record[NAV_LOG_RECORD_BYTES];
  uint8_t ready = 0;
  int finished = 0;
  long frames = 0;
  for (;;) {
    if (nav_replay_next_frame(replay, &inputs, &ready) != NAV_STATUS_OK) return -1;
    if (ready) {
      NavStatus status = nav_run_frame(computer, &inputs, telemetry, &fault);
      if (status != NAV_STATUS_OK) return refused("nav_run_frame", status, &fault), -1;
      if (write_record(out, telemetry)) return -1;
      frames++;
      continue;
    }
    if (finished) return frames;
    if (fread(record, 1, sizeof record, in) != sizeof record) {
      if (nav_replay_finish(replay) != NAV_STATUS_OK) return -1;
      finished = 1;
      continue;
    }
    NavStatus status = nav_replay_push(replay, record, &fault);
    if (status != NAV_STATUS_OK) return refused("nav_replay_push", status, &fault), -1;
  }
}

int main(int argc, char **argv) {
  static uint8_t start[NAV_REPLAY_START_BYTES];
  NavConfig config;
  NavGroundConstants ground;
  NavInitialState initial;
  NavTelemetry telemetry;
  NavFault fault;
  NavStatus status;
  if (argc != 3) {
    fprintf(stderr, "usage: %s REPLAY-IN REPLAY-OUT\n", argv[0]);
    return 2;
  }
  FILE *in = fopen(argv[1], "rb");
  FILE *out = fopen(argv[2], "wb");
  if (!in || !out || fread(start, 1, sizeof start, in) != sizeof start) {
    fprintf(stderr, "cannot read %s or write %s\n", argv[1], argv[2]);
    return 1;
  }
  status = nav_replay_start(replay, sizeof replay, start, sizeof start, &config, &ground,
                            &initial, &fault);
  if (status != NAV_STATUS_OK) return refused("nav_replay_start", status, &fault);
  status = nav_configure(computer, sizeof computer, &config, &ground, &initial, &fault);
  if (status != NAV_STATUS_OK) return refused("nav_configure", status, &fault);
  long frames = replay_log(in, out, &telemetry);
  if (frames <= 0 || fclose(out) != 0) return 1;
  fclose(in);
  printf("frames %ld time_s %.17g position_m %.17g %.17g %.17g imu_missing %u\n", frames,
         telemetry.time_s, telemetry.position_m[0], telemetry.position_m[1],
         telemetry.position_m[2], (unsigned)telemetry.health.imu_missing);
  return 0;
}
