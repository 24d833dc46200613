// SPDX-License-Identifier: BSD-3-Clause
/* How a C controller's messages travel (doc/external_controller.md): LCM over UDP multicast
 * (carrier_lcm.c) or Eclipse iceoryx's shared memory through its C binding (carrier_iceoryx.c,
 * doc/iceoryx.md). Either carries the bytes LCM encodes, one message each; the law and its
 * bookkeeping (the example's state_space_controller.c) see only those bytes. Part of the
 * installed library flexloop_c_controller (<flexloop/carrier.h>, doc/install.md). */
#ifndef FLEXLOOP_C_CONTROLLER_CARRIER_H
#define FLEXLOOP_C_CONTROLLER_CARRIER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FLEXLOOP_SENSOR_CHANNEL "FLEXLOOP_SENSOR"
#define FLEXLOOP_COMMAND_CHANNEL "FLEXLOOP_COMMAND"

/* Called with the bytes of each FLEXLOOP_SENSOR message, as received. */
typedef void (*FlexloopCarrierDeliver)(void* user, const void* data, int size);

typedef struct FlexloopCarrier FlexloopCarrier;
struct FlexloopCarrier {
  /* Delivers every message ready; when there is none, waits up to timeout_ms for one (0: just
   * looks). Returns how many it delivered, -1 when the carrier failed. */
  int (*receive)(FlexloopCarrier* self, int timeout_ms);
  /* A buffer of `size` bytes to encode one FLEXLOOP_COMMAND message into, or NULL when none is
   * available (the message is then not sent). */
  void* (*loan)(FlexloopCarrier* self, int size);
  /* Sends the `size` bytes of a buffer from loan(); discard() gives one back unsent. */
  void (*send)(FlexloopCarrier* self, void* buffer, int size);
  void (*discard)(FlexloopCarrier* self, void* buffer);
  void (*close)(FlexloopCarrier* self);
  char description[160]; /* e.g. "LCM udpm://...", for the first line the controller prints */
  FlexloopCarrierDeliver deliver;
  void* user;
};

/* The LCM carrier at `url` (it must have ttl=0); exits 2 on a bad URL, 1 when LCM fails. */
FlexloopCarrier* flexloop_carrier_lcm_open(const char* url, FlexloopCarrierDeliver deliver,
                                           void* user);

/* The iceoryx carrier: registers with the host's RouDi; exits 2, saying why, when none runs. */
FlexloopCarrier* flexloop_carrier_iceoryx_open(FlexloopCarrierDeliver deliver, void* user);

#ifdef __cplusplus
}
#endif

#endif
