/* How the C controller's messages travel (doc/external_controller.md): LCM over UDP multicast
 * (carrier_lcm.c) or Eclipse iceoryx's shared memory through its C binding (carrier_iceoryx.c,
 * doc/iceoryx.md). Either carries the bytes LCM encodes, one message each; the law and its
 * bookkeeping (state_space_controller.c) see only those bytes. */
#ifndef FLEXLOOP_C_CONTROLLER_CARRIER_H
#define FLEXLOOP_C_CONTROLLER_CARRIER_H

#include <stdint.h>

#define FLEXLOOP_SENSOR_CHANNEL "FLEXLOOP_SENSOR"
#define FLEXLOOP_COMMAND_CHANNEL "FLEXLOOP_COMMAND"

/* Called with the bytes of each FLEXLOOP_SENSOR message, as received. */
typedef void (*CarrierDeliver)(void* user, const void* data, int size);

typedef struct Carrier Carrier;
struct Carrier {
  /* Delivers every message ready; when there is none, waits up to timeout_ms for one (0: just
   * looks). Returns how many it delivered, -1 when the carrier failed. */
  int (*receive)(Carrier* self, int timeout_ms);
  /* A buffer of `size` bytes to encode one FLEXLOOP_COMMAND message into, or NULL when none is
   * available (the message is then not sent). */
  void* (*loan)(Carrier* self, int size);
  /* Sends the `size` bytes of a buffer from loan(); discard() gives one back unsent. */
  void (*send)(Carrier* self, void* buffer, int size);
  void (*discard)(Carrier* self, void* buffer);
  void (*close)(Carrier* self);
  char description[160]; /* e.g. "LCM udpm://...", for the first line the controller prints */
  CarrierDeliver deliver;
  void* user;
};

/* The LCM carrier at `url` (it must have ttl=0); exits 2 on a bad URL, 1 when LCM fails. */
Carrier* carrier_lcm_open(const char* url, CarrierDeliver deliver, void* user);

/* The iceoryx carrier: registers with the host's RouDi; exits 2, saying why, when none runs. */
Carrier* carrier_iceoryx_open(CarrierDeliver deliver, void* user);

#endif
