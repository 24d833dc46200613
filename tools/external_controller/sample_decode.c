// SPDX-License-Identifier: BSD-3-Clause
#include <flexloop/sample_decode.h>

#include <lcm/lcm_coretypes.h>
#include <string.h>

/* Fields in msgs/sensor_sample_t.lcm's order, each with LCM's own decoder of its type. */
int flexloop_decode_sample(const void* data, int size, int sensors, FlexloopSensorSample* s) {
  flexloop_msgs_sensor_sample_t* m = &s->msg;
  int64_t hash = 0;
  int at = 0, n;
#define FIELD(decoder, field, count)                                      \
  if ((n = decoder(data, at, size - at, (field), (count))) < 0) return 0; \
  at += n
  FIELD(__int64_t_decode_array, &hash, 1);
  if (hash != __flexloop_msgs_sensor_sample_t_get_hash()) return 0;
  FIELD(__int64_t_decode_array, &m->t_ns, 1);
  FIELD(__int64_t_decode_array, &m->seq, 1);
  FIELD(__int64_t_decode_array, &m->plant_epoch, 1);
  FIELD(__int16_t_decode_array, &m->n_sensors, 1);
  FIELD(__int16_t_decode_array, &m->n_performance, 1);
  if (m->n_sensors != sensors || sensors < 1 || sensors > FLEXLOOP_MAX_CHANNELS) return 0;
  if (m->n_performance < 1 || m->n_performance > FLEXLOOP_MAX_CHANNELS) return 0;
  m->sensors = s->sensors;
  m->performance = s->performance;
  FIELD(__double_decode_array, m->sensors, m->n_sensors);
  FIELD(__double_decode_array, m->performance, m->n_performance);
  FIELD(__int64_t_decode_array, &m->applied_seq, 1);
  FIELD(__double_decode_array, &m->applied_scale, 1);
#undef FIELD
  return at == size;
}

int flexloop_decode_sample_matches_lcm_gen(void) {
  double sensors[3] = {1.5, -2.25, 3e-9}, performance[2] = {-4.0, 5.125};
  const flexloop_msgs_sensor_sample_t probe = {.t_ns = 11,
                                               .seq = 12,
                                               .plant_epoch = -13,
                                               .n_sensors = 3,
                                               .n_performance = 2,
                                               .sensors = sensors,
                                               .performance = performance,
                                               .applied_seq = 14,
                                               .applied_scale = 0.75};
  unsigned char bytes[256];
  const int size = flexloop_msgs_sensor_sample_t_encode(bytes, 0, sizeof bytes, &probe);
  FlexloopSensorSample s;
  if (size <= 0 || !flexloop_decode_sample(bytes, size, 3, &s)) return 0;
  const flexloop_msgs_sensor_sample_t* m = &s.msg;
  return m->t_ns == probe.t_ns && m->seq == probe.seq && m->plant_epoch == probe.plant_epoch &&
         m->n_sensors == 3 && m->n_performance == 2 &&
         memcmp(m->sensors, sensors, sizeof sensors) == 0 &&
         memcmp(m->performance, performance, sizeof performance) == 0 &&
         m->applied_seq == probe.applied_seq && m->applied_scale == probe.applied_scale;
}
