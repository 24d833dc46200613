// SPDX-License-Identifier: BSD-3-Clause
/* The iceoryx carrier of the C controller (carrier.h), on iceoryx 2.0's C binding only. The wire
 * contract is doc/iceoryx.md: the LCM channel name is the iceoryx service {"flexloop", <channel>,
 * "lcm"}; one chunk holds one message as LCM encodes it, its user-payload size the encoded
 * length; the publisher keeps no history, the subscriber asks for none and queues 30 chunks.
 * Receiving takes every chunk ready, hands its bytes on and releases it; sending loans a chunk of
 * the encoded size, which the caller encodes into, and publishes it. Nothing is allocated after
 * set-up. */
#include <errno.h>
#include <iceoryx_binding_c/chunk.h>
#include <iceoryx_binding_c/log.h>
#include <iceoryx_binding_c/publisher.h>
#include <iceoryx_binding_c/runtime.h>
#include <iceoryx_binding_c/subscriber.h>
#include <iceoryx_binding_c/wait_set.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <flexloop/carrier.h>

/* RouDi's socket: iceoryx 2.0's IOX_UDS_SOCKET_PATH_PREFIX ("/tmp/") and RouDi's name. */
#define ROUDI_SOCKET "/tmp/roudi"

enum {
  kQueueCapacity = 30, /* as LCM's queue (doc/iceoryx.md) */
  kAlignment = 8,      /* the payload's alignment: LCM's bytes need none; the binding's default */
  /* iceoryx 2.0's chunk header (iceoryx_posh/mepoo/chunk_header.hpp), which the 2.0 C binding
   * has no accessor for: the version byte sits at offset 4 in every version; version 1 has the
   * user-payload size at 28 and its alignment at 32. open() checks both on a chunk of its own. */
  kHeaderVersionAt = 4,
  kHeaderVersion = 1,
  kPayloadSizeAt = 28,
  kPayloadAlignmentAt = 32,
  kProbeBytes = 58 /* the smallest command: one actuator */
};

typedef struct {
  FlexloopCarrier base; /* first: a FlexloopCarrier* is an IceoryxCarrier* */
  iox_sub_storage_t sub_storage;
  iox_pub_storage_t pub_storage;
  iox_ws_storage_t ws_storage;
  iox_sub_t sub;
  iox_pub_t pub;
  iox_ws_t ws;
  iox_notification_info_t events[1];
  char name[64];
} IceoryxCarrier;

static void iceoryx_fail(const char* what) {
  fprintf(stderr, "flexloop-c-controller: iceoryx: %s\n", what);
  exit(2);
}

static uint32_t header_u32(const void* payload, int at) {
  const unsigned char* h = (const unsigned char*)iox_chunk_header_from_user_payload_const(payload);
  uint32_t v;
  memcpy(&v, h + at, sizeof v);
  return v;
}

/* The chunk's user-payload size: the message's encoded length (-1: not a version-1 header). */
static int user_payload_size(const void* payload) {
  const unsigned char* h = (const unsigned char*)iox_chunk_header_from_user_payload_const(payload);
  const uint32_t size = header_u32(payload, kPayloadSizeAt);
  return h[kHeaderVersionAt] == kHeaderVersion && size <= 0x7fffffff ? (int)size : -1;
}

static int take_all(IceoryxCarrier* self) {
  int handled = 0;
  const void* chunk = NULL;
  while (iox_sub_take_chunk(self->sub, &chunk) == ChunkReceiveResult_SUCCESS) {
    self->base.deliver(self->base.user, chunk, user_payload_size(chunk));
    iox_sub_release_chunk(self->sub, chunk);
    ++handled;
  }
  return handled;
}

static int iceoryx_receive(FlexloopCarrier* base, int timeout_ms) {
  IceoryxCarrier* self = (IceoryxCarrier*)base;
  const int handled = take_all(self);
  if (handled > 0 || timeout_ms <= 0) return handled;
  /* Sleeps on the wait set's semaphore, which a publish posts while the queue has data. */
  const struct timespec timeout = {timeout_ms / 1000, (long)(timeout_ms % 1000) * 1000000L};
  uint64_t missed = 0;
  iox_ws_timed_wait(self->ws, timeout, self->events, 1, &missed);
  return take_all(self);
}

static void* iceoryx_loan(FlexloopCarrier* base, int size) {
  IceoryxCarrier* self = (IceoryxCarrier*)base;
  void* chunk = NULL;
  if (size <= 0 || iox_pub_loan_aligned_chunk(self->pub, &chunk, (uint32_t)size, kAlignment) !=
                       AllocationResult_SUCCESS)
    return NULL;
  return chunk;
}

static void iceoryx_send(FlexloopCarrier* base, void* buffer, int size) {
  (void)size; /* the chunk was loaned with it */
  iox_pub_publish_chunk(((IceoryxCarrier*)base)->pub, buffer);
}

static void iceoryx_discard(FlexloopCarrier* base, void* buffer) {
  iox_pub_release_chunk(((IceoryxCarrier*)base)->pub, buffer);
}

/* The wait set first (it detaches the subscriber), then the ports, then the runtime: the process
 * deregisters from RouDi and its socket and lock in /tmp go. */
static void iceoryx_close(FlexloopCarrier* base) {
  IceoryxCarrier* self = (IceoryxCarrier*)base;
  iox_ws_deinit(self->ws);
  iox_sub_deinit(self->sub);
  iox_pub_deinit(self->pub);
  iox_runtime_shutdown();
  free(self);
}

/* iox_runtime_init waits up to a minute for RouDi and then aborts: ask RouDi's socket first. */
static void require_roudi(void) {
  struct sockaddr_un address = {.sun_family = AF_UNIX};
  strncpy(address.sun_path, ROUDI_SOCKET, sizeof address.sun_path - 1);
  const int fd = socket(AF_UNIX, SOCK_DGRAM, 0);
  const int connected = fd >= 0 && connect(fd, (struct sockaddr*)&address, sizeof address) == 0;
  const int error = errno;
  if (fd >= 0) close(fd);
  if (connected) return;
  char what[256];
  snprintf(what, sizeof what,
           "no RouDi runs on this host (%s: %s); start one first, e.g. `flexloop roudi`",
           ROUDI_SOCKET, strerror(error));
  iceoryx_fail(what);
}

/* The header layout user_payload_size() reads, checked on a chunk loaned and given back. */
static void check_chunk_header(IceoryxCarrier* self) {
  void* chunk = NULL;
  if (iox_pub_loan_aligned_chunk(self->pub, &chunk, kProbeBytes, kAlignment) !=
      AllocationResult_SUCCESS)
    iceoryx_fail(
        "RouDi has no chunk for a 58-byte command (is its mempool sized for flexloop's "
        "messages? `flexloop roudi` sizes it)");
  const int ok = user_payload_size(chunk) == kProbeBytes &&
                 header_u32(chunk, kPayloadAlignmentAt) == kAlignment;
  iox_pub_release_chunk(self->pub, chunk);
  if (!ok)
    iceoryx_fail(
        "the chunk header is not iceoryx 2.0's (version 1): this example reads its "
        "user-payload size at offset 28");
}

static void open_ports(IceoryxCarrier* self) {
  iox_sub_options_t sub_options;
  iox_sub_options_init(&sub_options);
  sub_options.queueCapacity = kQueueCapacity;
  sub_options.historyRequest = 0;
  self->sub =
      iox_sub_init(&self->sub_storage, "flexloop", FLEXLOOP_SENSOR_CHANNEL, "lcm", &sub_options);
  iox_pub_options_t pub_options;
  iox_pub_options_init(&pub_options);
  pub_options.historyCapacity = 0;
  self->pub =
      iox_pub_init(&self->pub_storage, "flexloop", FLEXLOOP_COMMAND_CHANNEL, "lcm", &pub_options);
  self->ws = iox_ws_init(&self->ws_storage);
  if (!self->sub || !self->pub || !self->ws)
    iceoryx_fail("cannot make the subscriber or publisher");
  if (iox_ws_attach_subscriber_state(self->ws, self->sub, SubscriberState_HAS_DATA, 0, NULL) !=
      WaitSetResult_SUCCESS)
    iceoryx_fail("cannot attach the subscriber of " FLEXLOOP_SENSOR_CHANNEL " to the wait set");
}

FlexloopCarrier* flexloop_carrier_iceoryx_open(FlexloopCarrierDeliver deliver, void* user) {
  require_roudi();
  IceoryxCarrier* self = calloc(1, sizeof *self);
  if (!self) {
    fprintf(stderr, "flexloop-c-controller: out of memory\n");
    exit(1);
  }
  iox_set_loglevel(Iceoryx_LogLevel_Warn); /* iceoryx logs to stdout; the controller's is its own */
  snprintf(self->name, sizeof self->name, "flexloop_c_controller_%ld", (long)getpid());
  iox_runtime_init(self->name); /* unique on the host: RouDi refuses a name registered twice */
  open_ports(self);
  check_chunk_header(self);
  self->base = (FlexloopCarrier){.receive = iceoryx_receive,
                                 .loan = iceoryx_loan,
                                 .send = iceoryx_send,
                                 .discard = iceoryx_discard,
                                 .close = iceoryx_close,
                                 .deliver = deliver,
                                 .user = user};
  snprintf(self->base.description, sizeof self->base.description,
           "iceoryx (RouDi at %s, runtime %s)", ROUDI_SOCKET, self->name);
  return &self->base;
}
