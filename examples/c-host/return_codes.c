/* Provokes every return code of the C interface (nav.h) from C and prints one line per case:
 *
 *   CASE status=S argument=A field=F param=PATH companion=PATH input=I index=N
 *
 * nav-c/tests/c_host.rs runs it and checks every line. The ground constants are the built-in
 * scenario's launch: ground_constants.h is `nav-sim ground-constants --format c`. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "nav.h"

static uint64_t computer[NAV_COMPUTER_MAX_BYTES / 8];
static uint64_t replay[NAV_REPLAY_MAX_BYTES / 8];

#include "ground_constants.h"

#define GROUND NAV_GROUND_CONSTANTS

static const NavInitialState INITIAL = {
    {1.0, 0.0, 0.0, 0.0}, {0.0, 500e3, 0.0}, {7600.0, 0.0, 0.0}, 600.0};

static void print_case(const char *name, NavStatus status, const NavFault *fault) {
  const char *param = nav_param_path(fault->param);
  const char *companion = nav_param_path(fault->companion);
  printf("%s status=%d argument=%d field=%d param=%s companion=%s input=%d index=%u\n", name,
         (int)status, (int)fault->argument, (int)fault->field, param ? param : "-",
         companion ? companion : "-", (int)fault->input, (unsigned)fault->index);
}

static NavStatus configure(const NavConfig *config, const NavGroundConstants *ground,
                           NavFault *fault) {
  return nav_configure(computer, sizeof computer, config, ground, &INITIAL, fault);
}

/* The frame with one IMU sample at the first frame's end. */
static NavFrameInputs quiet_frame(void) {
  NavFrameInputs inputs;
  memset(&inputs, 0, sizeof inputs);
  inputs.imu_present = 1;
  inputs.imu.sequence = 1;
  inputs.imu.time_s = 600.002;
  return inputs;
}

static void frame_cases(void) {
  NavFrameInputs inputs = quiet_frame();
  NavTelemetry telemetry;
  NavFault fault;
  print_case("frame_before_configure",
             nav_run_frame(computer, &inputs, &telemetry, &fault), &fault);
  NavConfig config;
  nav_config_defaults(&config);
  print_case("configure", configure(&config, &GROUND, &fault), &fault);
  print_case("frame", nav_run_frame(computer, &inputs, &telemetry, &fault), &fault);
  printf("frame telemetry frame=%u imu_missing=%u\n", (unsigned)telemetry.frame,
         (unsigned)telemetry.health.imu_missing);
  print_case("frame_null_inputs", nav_run_frame(computer, NULL, &telemetry, &fault), &fault);
  print_case("frame_null_telemetry", nav_run_frame(computer, &inputs, NULL, &fault), &fault);
  print_case("frame_null_memory", nav_run_frame(NULL, &inputs, &telemetry, &fault), &fault);
  print_case("frame_misaligned",
             nav_run_frame((uint8_t *)computer + 4, &inputs, &telemetry, &fault), &fault);
  inputs.imu_present = 2;
  print_case("frame_imu_present_2", nav_run_frame(computer, &inputs, &telemetry, &fault),
             &fault);
  inputs = quiet_frame();
  inputs.star_count = NAV_FRAME_STAR_CAPACITY + 1;
  print_case("frame_too_many_stars", nav_run_frame(computer, &inputs, &telemetry, &fault),
             &fault);
  inputs = quiet_frame();
  inputs.gnss_count = NAV_FRAME_GNSS_CAPACITY + 1;
  print_case("frame_too_many_fixes", nav_run_frame(computer, &inputs, &telemetry, &fault),
             &fault);
  inputs = quiet_frame();
  inputs.gnss_count = 2;
  inputs.gnss[1].velocity_present = 7;
  print_case("frame_velocity_present_7", nav_run_frame(computer, &inputs, &telemetry, &fault),
             &fault);
  /* A refused frame ran nothing: the next frame is the second. */
  inputs = quiet_frame();
  inputs.imu.sequence = 2;
  inputs.imu.time_s = 600.004;
  nav_run_frame(computer, &inputs, &telemetry, &fault);
  printf("after refused frames frame=%u imu_missing=%u\n", (unsigned)telemetry.frame,
         (unsigned)telemetry.health.imu_missing);
}

static void configure_cases(void) {
  NavConfig config;
  NavGroundConstants ground = GROUND;
  NavFault fault;
  NavFrameInputs inputs = quiet_frame();
  NavTelemetry telemetry;
  nav_config_defaults(&config);
  print_case("configure_null_memory",
             nav_configure(NULL, sizeof computer, &config, &ground, &INITIAL, &fault), &fault);
  print_case("configure_null_config", configure(NULL, &ground, &fault), &fault);
  print_case("configure_null_ground", configure(&config, NULL, &fault), &fault);
  print_case("configure_null_initial",
             nav_configure(computer, sizeof computer, &config, &ground, NULL, &fault), &fault);
  print_case("configure_misaligned",
             nav_configure((uint8_t *)computer + 1, sizeof computer - 8, &config, &ground,
                           &INITIAL, &fault),
             &fault);
  print_case("configure_too_small",
             nav_configure(computer, nav_computer_size() - 1, &config, &ground, &INITIAL,
                           &fault),
             &fault);
  config.gnss_noise_m = -1.0;
  print_case("configure_gnss_noise_negative", configure(&config, &ground, &fault), &fault);
  /* A refused configuration leaves no computer. */
  print_case("frame_after_refused_configure",
             nav_run_frame(computer, &inputs, &telemetry, &fault), &fault);
  nav_config_defaults(&config);
  config.filter_discretisation_order = 2.5;
  print_case("configure_order_not_integer", configure(&config, &ground, &fault), &fault);
  nav_config_defaults(&config);
  config.filter_gnss_error_sigma_m = 5.0;
  print_case("configure_companion_off", configure(&config, &ground, &fault), &fault);
  nav_config_defaults(&config);
  ground.earth_axis_ecef[0] = 1.0;
  ground.earth_axis_ecef[2] = 0.0;
  print_case("configure_earth_axis", configure(&config, &ground, &fault), &fault);
  ground = GROUND;
  ground.launch_epoch_gps_seconds_of_week = 604800.0;
  print_case("configure_epoch", configure(&config, &ground, &fault), &fault);
  printf("configure_null_fault status=%d\n", (int)configure(&config, &GROUND, NULL));
}

static void replay_cases(void) {
  static uint8_t zeros[NAV_REPLAY_START_BYTES];
  uint8_t record[NAV_LOG_RECORD_BYTES];
  NavConfig config;
  NavGroundConstants ground;
  NavInitialState initial;
  NavFault fault;
  memset(record, 0, sizeof record);
  print_case("replay_push_before_start", nav_replay_push(replay, record, &fault), &fault);
  print_case("replay_start_zeros",
             nav_replay_start(replay, sizeof replay, zeros, sizeof zeros, &config, &ground,
                              &initial, &fault),
             &fault);
  print_case("replay_start_short",
             nav_replay_start(replay, sizeof replay, zeros, 10, &config, &ground, &initial,
                              &fault),
             &fault);
}

int main(void) {
  printf("sizes computer=%s replay=%s\n",
         nav_computer_size() <= sizeof computer ? "fits" : "too-large",
         nav_replay_size() <= sizeof replay ? "fits" : "too-large");
  frame_cases();
  configure_cases();
  replay_cases();
  printf("param_path none=%s first=%s last=%s beyond=%s\n",
         nav_param_path(NAV_PARAM_NONE) ? "set" : "null", nav_param_path(1),
         nav_param_path(NAV_PARAMS), nav_param_path(NAV_PARAMS + 1) ? "set" : "null");
  return 0;
}
