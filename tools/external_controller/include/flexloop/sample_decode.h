// SPDX-License-Identifier: BSD-3-Clause
/* FLEXLOOP_SENSOR's bytes into a sensor_sample_t without allocating: lcm-gen's C decoder
 * allocates the two arrays on every call; this one decodes into arrays the caller owns. */
#ifndef FLEXLOOP_C_CONTROLLER_SAMPLE_DECODE_H
#define FLEXLOOP_C_CONTROLLER_SAMPLE_DECODE_H

#include <flexloop/flexloop_msgs_sensor_sample_t.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
  FLEXLOOP_MAX_CHANNELS = 64
}; /* each count of a message is 1 to 64 (doc/external_controller.md) */

typedef struct {
  flexloop_msgs_sensor_sample_t msg; /* its arrays point at the two below */
  double sensors[FLEXLOOP_MAX_CHANNELS], performance[FLEXLOOP_MAX_CHANNELS];
} FlexloopSensorSample;

/* 1 when `data` is exactly one sensor_sample_t (fingerprint first) with `sensors` sensor readings
 * and 1 to 64 performance readings, decoded into s; 0 otherwise. The sensor count is read before
 * the arrays are decoded, as the plant reads a command's. */
int flexloop_decode_sample(const void* data, int size, int sensors, FlexloopSensorSample* s);

/* 1 when flexloop_decode_sample reads back what lcm-gen's encoder writes from
 * msgs/sensor_sample_t.lcm (field for field, on a sample of distinct values): the field order it
 * follows is that file's. */
int flexloop_decode_sample_matches_lcm_gen(void);

#ifdef __cplusplus
}
#endif

#endif
