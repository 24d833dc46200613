// SPDX-License-Identifier: BSD-3-Clause
/* The LCM carrier of the C controller (carrier.h): one UDP multicast datagram per message. */
#include <lcm/lcm.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <flexloop/carrier.h>

/* The largest actuator_command_t: 50 + 8 * 64 bytes (doc/external_controller.md, section 3). */
enum { kMaxCommandBytes = 50 + 8 * 64 };

typedef struct {
  FlexloopCarrier base; /* first: a FlexloopCarrier* is a LcmCarrier* */
  lcm_t* lcm;
  unsigned char command[kMaxCommandBytes];
} LcmCarrier;

static void on_datagram(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  (void)channel;
  FlexloopCarrier* self = user;
  self->deliver(self->user, rbuf->data, (int)rbuf->data_size);
}

static int lcm_carrier_receive(FlexloopCarrier* base, int timeout_ms) {
  LcmCarrier* self = (LcmCarrier*)base;
  const int handled = lcm_handle_timeout(self->lcm, timeout_ms);
  return handled < 0 ? -1 : handled;
}

static void* lcm_carrier_loan(FlexloopCarrier* base, int size) {
  LcmCarrier* self = (LcmCarrier*)base;
  return size > 0 && size <= kMaxCommandBytes ? self->command : NULL;
}

static void lcm_carrier_send(FlexloopCarrier* base, void* buffer, int size) {
  lcm_publish(((LcmCarrier*)base)->lcm, FLEXLOOP_COMMAND_CHANNEL, buffer, (unsigned int)size);
}

static void lcm_carrier_discard(FlexloopCarrier* base, void* buffer) {
  (void)base;
  (void)buffer;
}

static void lcm_carrier_close(FlexloopCarrier* base) {
  LcmCarrier* self = (LcmCarrier*)base;
  lcm_destroy(self->lcm);
  free(self);
}

FlexloopCarrier* flexloop_carrier_lcm_open(const char* url, FlexloopCarrierDeliver deliver,
                                           void* user) {
  if (strstr(url, "ttl=0") == NULL) {
    fprintf(stderr, "flexloop-c-controller: the LCM URL must have ttl=0 (got %s)\n", url);
    exit(2);
  }
  LcmCarrier* self = calloc(1, sizeof *self);
  if (!self) {
    fprintf(stderr, "flexloop-c-controller: out of memory\n");
    exit(1);
  }
  self->lcm = lcm_create(url);
  if (!self->lcm) {
    fprintf(stderr, "flexloop-c-controller: LCM unavailable at %s\n", url);
    exit(1);
  }
  self->base = (FlexloopCarrier){.receive = lcm_carrier_receive,
                                 .loan = lcm_carrier_loan,
                                 .send = lcm_carrier_send,
                                 .discard = lcm_carrier_discard,
                                 .close = lcm_carrier_close,
                                 .deliver = deliver,
                                 .user = user};
  snprintf(self->base.description, sizeof self->base.description, "LCM %s", url);
  lcm_subscribe(self->lcm, FLEXLOOP_SENSOR_CHANNEL, on_datagram, &self->base);
  return &self->base;
}
