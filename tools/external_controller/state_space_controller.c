// SPDX-License-Identifier: BSD-3-Clause
/* An external controller in plain C: what a user's own controller process looks like
 * (doc/external_controller.md is the contract it follows). Of flexloop it links only the C
 * controller library (libflexloop_c_controller: the carriers over the LCM C library or iceoryx's
 * C binding, doc/iceoryx.md; the sample decoder; the C types `lcm-gen -c` makes from msgs/), as
 * installed (doc/install.md); besides, cJSON. No flexloop C++ code.
 *
 * It runs the state-space controller of a loop artefact (`flexloop build SCENE -o LOOP.json` of a
 * scene with [controller] type = "state_space": the artefact's "controller" object is the
 * controller file discretised at the loop's rate, in the channel map's order, with the plant's
 * actuator -> sensor feedthrough D22, the feedthrough delay d, the command limits and the
 * anti-windup policy) and answers every sensor sample with the law of doc/controllers.md:
 *
 *   f = y - D22 u_{k-1-d},  u = clamp((I - D D22)^-1 (C x + D f)),  x+ = A x + B (f + D22 u)
 *
 * A new plant_epoch (the plant restarted) resets the controller. Every sample says what the
 * actuators held over the period before it: applied_scale times the answer to sample applied_seq
 * (0: zero). A gap of --safe-after or more samples (the plant has applied its safe command, a ramp
 * of the held answer to zero) sets every remembered command to that one; otherwise, when it is
 * not the last answer as sent (a late or lost answer, or the ramp), it replaces the last one
 * remembered, so that the force removed from the measurement is the force in it. (The state x is
 * kept as it was: flexloop's own controller also moves x to a state that produces the held
 * command, a least-squares step this example leaves out.)
 *
 * With --record FILE it writes, when it ends, the samples it did not answer (lost on the way: gaps
 * in seq) as `flexloop replay --controller-record` reads them.
 *
 * The messages travel by a carrier (<flexloop/carrier.h>): LCM (carrier_lcm.c, the default) or
 * iceoryx's shared memory (carrier_iceoryx.c); this file sees only their bytes.
 *
 *   flexloop-c-controller LOOP.json [--transport lcm|iceoryx] [--url URL] [--spin] [--duration S]
 *                                   [--safe-after N] [--record FILE]
 *
 * Over LCM run it inside the plant's private namespace (tools/netns-run), beside `flexloop plant
 * LOOP.json`; over iceoryx beside `flexloop plant LOOP.json --transport iceoryx` and a running
 * RouDi (`flexloop roudi`).
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <flexloop/carrier.h>
#include <flexloop/flexloop_msgs_actuator_command_t.h>
#include <flexloop/sample_decode.h>

enum { kMaxHistory = 33, kRemembered = 64, kMaxGaps = 4096 };

typedef struct {
  int nx, ns, nc, delay, hold;
  double *A, *B, *H, *F, *BF; /* row-major; H = (I - D F)^-1 [C D], BF = B F */
  double *u_min, *u_max;
  double *x, *x_next, *f, *v, *history; /* history: kMaxHistory x nc, ring */
  int head;
  int started;
  int64_t epoch, last_seq, safe_after;
  double* sent;      /* kRemembered x nc: the answers to the last samples, by seq */
  int64_t* sent_seq; /* kRemembered */
  double* held;      /* nc: the answer the plant holds (it may hold one longer than kRemembered) */
  int64_t held_seq;
  double* applied; /* nc: what the plant held over the period before the current sample */
  FlexloopCarrier* carrier;
  FlexloopSensorSample sample; /* the message being answered, decoded */
  flexloop_msgs_actuator_command_t cmd;
  int64_t answered, undecoded, unsent;
  /* The samples not answered, as ranges of seq (kMaxGaps at most; else, or after a second plant
   * run, the record is incomplete). */
  int64_t gap_first[kMaxGaps], gap_last[kMaxGaps];
  int gaps, gaps_incomplete;
} Controller;

static volatile sig_atomic_t stop_requested = 0;
static void on_signal(int s) {
  (void)s;
  stop_requested = 1;
}

static void fail(const char* file, const char* what) {
  fprintf(stderr, "flexloop-c-controller: %s: %s\n", file, what);
  exit(2);
}

static int64_t now_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (int64_t)t.tv_sec * 1000000000LL + t.tv_nsec;
}

static double* zeros(int n) {
  double* p = calloc((size_t)(n > 0 ? n : 1), sizeof(double));
  if (!p) {
    fprintf(stderr, "flexloop-c-controller: out of memory\n");
    exit(1);
  }
  return p;
}

/* rows x cols matrix from a JSON list of rows, row-major. */
static double* matrix(const cJSON* obj, const char* key, int rows, int cols, const char* file) {
  const cJSON* m = cJSON_GetObjectItemCaseSensitive(obj, key);
  char what[200];
  if (!cJSON_IsArray(m) || cJSON_GetArraySize(m) != rows) {
    snprintf(what, sizeof what, "key 'controller': key '%s' must be a list of %d rows", key, rows);
    fail(file, what);
  }
  double* out = zeros(rows * cols);
  for (int r = 0; r < rows; ++r) {
    const cJSON* row = cJSON_GetArrayItem(m, r);
    if (!cJSON_IsArray(row) || cJSON_GetArraySize(row) != cols) {
      snprintf(what, sizeof what, "key 'controller': key '%s' row %d must have %d entries", key,
               r + 1, cols);
      fail(file, what);
    }
    for (int c = 0; c < cols; ++c) {
      const cJSON* e = cJSON_GetArrayItem(row, c);
      if (!cJSON_IsNumber(e)) fail(file, "key 'controller': a matrix entry is not a number");
      out[r * cols + c] = e->valuedouble;
    }
  }
  return out;
}

/* The length of channels.<kind>: 1 to 64, as a message carries. */
static int count(const cJSON* channels, const char* kind, const char* file) {
  const cJSON* list = cJSON_GetObjectItemCaseSensitive(channels, kind);
  if (!cJSON_IsArray(list)) fail(file, "key 'channels': missing a list of channels");
  const int n = cJSON_GetArraySize(list);
  if (n < 1 || n > FLEXLOOP_MAX_CHANNELS) fail(file, "key 'channels': a list has 1 to 64 channels");
  return n;
}

/* Limits: none, one for every channel, or one per channel. */
static double* limits(const cJSON* obj, const char* key, int nc, double none, const char* file) {
  const cJSON* v = cJSON_GetObjectItemCaseSensitive(obj, key);
  double* out = zeros(nc);
  const int n = cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
  if (n != 0 && n != 1 && n != nc) fail(file, "key 'controller': a limit has the wrong count");
  for (int i = 0; i < nc; ++i) {
    const cJSON* e = n == 0 ? NULL : cJSON_GetArrayItem(v, n == 1 ? 0 : i);
    if (e && !cJSON_IsNumber(e)) fail(file, "key 'controller': a limit is not a number");
    out[i] = e ? e->valuedouble : none;
  }
  return out;
}

/* Solves M X = R in place for X (M: n x n, R: n x m; Gaussian elimination, partial pivoting). */
static int solve(double* M, double* R, int n, int m) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (fabs(M[i * n + k]) > fabs(M[p * n + k])) p = i;
    if (fabs(M[p * n + k]) < 1e-300) return 0;
    for (int j = 0; j < n; ++j) {
      const double t = M[k * n + j];
      M[k * n + j] = M[p * n + j];
      M[p * n + j] = t;
    }
    for (int j = 0; j < m; ++j) {
      const double t = R[k * m + j];
      R[k * m + j] = R[p * m + j];
      R[p * m + j] = t;
    }
    for (int i = k + 1; i < n; ++i) {
      const double l = M[i * n + k] / M[k * n + k];
      for (int j = k; j < n; ++j) M[i * n + j] -= l * M[k * n + j];
      for (int j = 0; j < m; ++j) R[i * m + j] -= l * R[k * m + j];
    }
  }
  for (int k = n - 1; k >= 0; --k)
    for (int j = 0; j < m; ++j) {
      double s = R[k * m + j];
      for (int i = k + 1; i < n; ++i) s -= M[k * n + i] * R[i * m + j];
      R[k * m + j] = s / M[k * n + k];
    }
  return 1;
}

static void load(Controller* c, const char* file) {
  FILE* in = fopen(file, "rb");
  if (!in) fail(file, "cannot be read");
  const long size = fseek(in, 0, SEEK_END) == 0 ? ftell(in) : -1;
  if (size < 0 || fseek(in, 0, SEEK_SET) != 0) fail(file, "must be a regular file (not a pipe)");
  char* text = malloc((size_t)size + 1);
  if (!text || fread(text, 1, (size_t)size, in) != (size_t)size) fail(file, "cannot be read");
  text[size] = 0;
  fclose(in);
  cJSON* root = cJSON_Parse(text);
  free(text);
  if (!root) fail(file, "is not valid JSON");
  const cJSON* channels = cJSON_GetObjectItemCaseSensitive(root, "channels");
  const cJSON* co = cJSON_GetObjectItemCaseSensitive(root, "controller");
  const cJSON* type = cJSON_GetObjectItemCaseSensitive(co, "type");
  if (!cJSON_IsString(type) || strcmp(type->valuestring, "state_space") != 0)
    fail(file,
         "key 'controller': key 'type' must be \"state_space\" (build the artefact from a "
         "scene with a state-space controller)");
  c->ns = count(channels, "sensors", file);
  c->nc = count(channels, "actuators", file);
  const cJSON* states = cJSON_GetObjectItemCaseSensitive(co, "states");
  if (!cJSON_IsNumber(states) || states->valueint < 0) fail(file, "key 'controller': key 'states'");
  c->nx = states->valueint;
  const int nx = c->nx, ns = c->ns, nc = c->nc;
  c->A = matrix(co, "A", nx, nx, file);
  c->B = matrix(co, "B", nx, ns, file);
  double* C = matrix(co, "C", nc, nx, file);
  double* D = matrix(co, "D", nc, ns, file);
  c->F = matrix(co, "feedthrough", ns, nc, file);
  const cJSON* delay = cJSON_GetObjectItemCaseSensitive(co, "feedthrough_delay");
  const double d = cJSON_IsNumber(delay) ? delay->valuedouble : 0;
  if (!(d >= 0 && d + 1 <= kMaxHistory))
    fail(file, "key 'controller': key 'feedthrough_delay' out of range");
  c->delay = (int)d;
  const cJSON* aw = cJSON_GetObjectItemCaseSensitive(co, "anti_windup");
  c->hold = cJSON_IsString(aw) && strcmp(aw->valuestring, "hold") == 0;
  c->u_min = limits(co, "u_min", nc, -INFINITY, file);
  c->u_max = limits(co, "u_max", nc, INFINITY, file);
  for (int i = 0; i < nc; ++i)
    if (!(c->u_min[i] <= c->u_max[i])) fail(file, "key 'controller': u_min must be <= u_max");
  cJSON_Delete(root);

  /* H = (I - D F)^-1 [C D]: nc x (nx + ns). */
  double* M = zeros(nc * nc);
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j) {
      double s = i == j ? 1.0 : 0.0;
      for (int k = 0; k < ns; ++k) s -= D[i * ns + k] * c->F[k * nc + j];
      M[i * nc + j] = s;
    }
  double* H = zeros(nc * (nx + ns));
  for (int i = 0; i < nc; ++i) {
    for (int j = 0; j < nx; ++j) H[i * (nx + ns) + j] = C[i * nx + j];
    for (int j = 0; j < ns; ++j) H[i * (nx + ns) + nx + j] = D[i * ns + j];
  }
  if (!solve(M, H, nc, nx + ns)) fail(file, "I - D D22 is singular: the loop is ill-posed");
  c->H = H; /* the first nx columns of each row act on x, the rest on f */
  c->BF = zeros(nx * nc);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nc; ++j) {
      double s = 0;
      for (int k = 0; k < ns; ++k) s += c->B[i * ns + k] * c->F[k * nc + j];
      c->BF[i * nc + j] = s;
    }
  free(M);
  free(C);
  free(D);
  c->x = zeros(nx);
  c->x_next = zeros(nx);
  c->f = zeros(ns);
  c->v = zeros(nc);
  c->history = zeros(kMaxHistory * nc);
  c->sent = zeros(kRemembered * nc);
  c->held = zeros(nc);
  c->applied = zeros(nc);
  c->held_seq = -1;
  c->sent_seq = calloc(kRemembered, sizeof(int64_t));
  if (!c->sent_seq) fail(file, "out of memory");
  c->cmd.n_commands = (int16_t)nc;
  c->cmd.commands = zeros(nc);
}

static void reset(Controller* c) {
  memset(c->x, 0, sizeof(double) * (size_t)(c->nx > 0 ? c->nx : 1));
  memset(c->history, 0, sizeof(double) * (size_t)(kMaxHistory * c->nc));
  memset(c->sent_seq, 0, sizeof(int64_t) * kRemembered);
  c->held_seq = -1;
}

/* The plant holds the answer to sample `applied`: remember it while it is in the ring. */
static void remember_held(Controller* c, int64_t applied) {
  if (applied <= 0 || c->sent_seq[applied % kRemembered] != applied) return;
  memcpy(c->held, c->sent + (applied % kRemembered) * c->nc, sizeof(double) * (size_t)c->nc);
  c->held_seq = applied;
}

/* What the plant held over the period before sample s, into c->applied: applied_scale times the
 * answer to applied_seq (the plant's own single multiply, so bit for bit); zero when that answer
 * is not remembered. Its force is what the sample's measurement contains. */
static const double* applied_command(Controller* c, const flexloop_msgs_sensor_sample_t* s) {
  remember_held(c, s->applied_seq);
  for (int i = 0; i < c->nc; ++i)
    c->applied[i] =
        s->applied_seq > 0 && s->applied_seq == c->held_seq ? s->applied_scale * c->held[i] : 0.0;
  return c->applied;
}

/* One sample: y (ns) -> the command in c->cmd.commands. */
static void step(Controller* c, const double* y) {
  const int nx = c->nx, ns = c->ns, nc = c->nc, n = kMaxHistory;
  const double* held = c->history + ((c->head - c->delay + n) % n) * nc;
  for (int i = 0; i < ns; ++i) {
    double s = y[i];
    for (int j = 0; j < nc; ++j) s -= c->F[i * nc + j] * held[j];
    c->f[i] = s;
  }
  double* u = c->cmd.commands;
  int clamped = 0;
  for (int i = 0; i < nc; ++i) {
    const double* h = c->H + i * (nx + ns);
    double s = 0;
    for (int j = 0; j < nx; ++j) s += h[j] * c->x[j];
    for (int j = 0; j < ns; ++j) s += h[nx + j] * c->f[j];
    u[i] = s < c->u_min[i] ? c->u_min[i] : (s > c->u_max[i] ? c->u_max[i] : s);
    clamped |= u[i] != s;
  }
  if (!(clamped && c->hold)) {
    for (int i = 0; i < nx; ++i) {
      double s = 0;
      for (int j = 0; j < nx; ++j) s += c->A[i * nx + j] * c->x[j];
      for (int j = 0; j < ns; ++j) s += c->B[i * ns + j] * c->f[j];
      for (int j = 0; j < nc; ++j) s += c->BF[i * nc + j] * u[j];
      c->x_next[i] = s;
    }
    memcpy(c->x, c->x_next, sizeof(double) * (size_t)nx);
  }
  c->head = (c->head + 1) % n;
  memcpy(c->history + c->head * nc, u, sizeof(double) * (size_t)nc);
}

static void record_gap(Controller* c, int64_t first, int64_t last) {
  if (last < first) return;
  if (c->gaps == kMaxGaps) {
    c->gaps_incomplete = 1;
    return;
  }
  c->gap_first[c->gaps] = first;
  c->gap_last[c->gaps] = last;
  ++c->gaps;
}

/* {"unanswered_samples": {"ranges": [[first, last], ...], "complete": true|false}} */
static int write_record(const Controller* c, const char* file) {
  FILE* out = fopen(file, "w");
  if (!out) return 0;
  fprintf(out, "{\"unanswered_samples\": {\"ranges\": [");
  for (int i = 0; i < c->gaps; ++i)
    fprintf(out, "%s[%lld, %lld]", i ? ", " : "", (long long)c->gap_first[i],
            (long long)c->gap_last[i]);
  fprintf(out, "], \"complete\": %s}}\n", c->gaps_incomplete ? "false" : "true");
  return fclose(out) == 0;
}

/* Follows the plant's run, what it applied and the samples lost (the bookkeeping above), then
 * steps the law: 1 when c->cmd holds the answer to s, 0 when s is not to be answered. */
static int answer(Controller* c, const flexloop_msgs_sensor_sample_t* s) {
  for (int i = 0; i < s->n_sensors; ++i)
    if (!isfinite(s->sensors[i])) return 0;
  if (!isfinite(s->applied_scale)) return 0;
  int64_t expected = c->last_seq + 1;
  if (!c->started || s->plant_epoch != c->epoch) {
    if (c->started) c->gaps_incomplete = 1; /* the record covers one plant run */
    expected = 1;
    reset(c); /* a new plant run starts from rest */
    c->epoch = s->plant_epoch;
    c->started = 1;
  } else if (s->seq <= c->last_seq) {
    return 0; /* a repeat or an older sample */
  } else if (s->seq - c->last_seq > c->safe_after) {
    const double* u = applied_command(c, s); /* the plant has been on its safe command */
    for (int k = 0; k < kMaxHistory; ++k)
      memcpy(c->history + k * c->nc, u, sizeof(double) * (size_t)c->nc);
  } else if (s->applied_seq != c->last_seq || s->applied_scale != 1.0) {
    memcpy(c->history + c->head * c->nc, applied_command(c, s), sizeof(double) * (size_t)c->nc);
  } else {
    remember_held(c, s->applied_seq); /* the plant holds the last answer */
  }
  record_gap(c, expected, s->seq - 1);
  c->last_seq = s->seq;
  step(c, s->sensors);
  memcpy(c->sent + (s->seq % kRemembered) * c->nc, c->cmd.commands, sizeof(double) * (size_t)c->nc);
  c->sent_seq[s->seq % kRemembered] = s->seq;
  c->cmd.seq += 1;
  c->cmd.answers_seq = s->seq;
  c->cmd.plant_epoch = s->plant_epoch;
  return 1;
}

/* Encodes c->cmd into a buffer the carrier lends (over iceoryx: a chunk of exactly the encoded
 * size in shared memory) and sends it. */
static void send_command(Controller* c) {
  FlexloopCarrier* carrier = c->carrier;
  const int size = flexloop_msgs_actuator_command_t_encoded_size(&c->cmd);
  void* buffer = carrier->loan(carrier, size);
  if (!buffer) {
    ++c->unsent;
    return;
  }
  if (flexloop_msgs_actuator_command_t_encode(buffer, 0, size, &c->cmd) != size) {
    carrier->discard(carrier, buffer);
    ++c->unsent;
    return;
  }
  carrier->send(carrier, buffer, size);
  ++c->answered;
}

/* One FLEXLOOP_SENSOR message's bytes, from either carrier. */
static void on_message(void* user, const void* data, int size) {
  Controller* c = user;
  const int64_t t0 = now_ns();
  if (!flexloop_decode_sample(data, size, c->ns, &c->sample)) {
    ++c->undecoded; /* not a sample of this loop */
    return;
  }
  if (!answer(c, &c->sample.msg)) return;
  const int64_t t1 = now_ns();
  c->cmd.controller_compute_ns = t1 - t0;
  c->cmd.t_ns = t1;
  send_command(c);
}

typedef struct {
  const char* loop;
  const char* url;
  const char* record;
  int iceoryx, spin;
  double duration_s;
} Options;

static void usage(void) {
  printf(
      "usage: flexloop-c-controller LOOP.json [--transport lcm|iceoryx] [--url URL] [--spin]\n"
      "                             [--duration S] [--safe-after N] [--record FILE]\n"
      "Answers every FLEXLOOP_SENSOR sample with the loop artefact's state-space controller.\n"
      "--transport: LCM (default; --url, else $LCM_DEFAULT_URL, ttl=0) or iceoryx (the host's\n"
      "  RouDi: start `flexloop roudi` first).\n"
      "--spin: poll for samples instead of sleeping until one comes (use a core of its own).\n"
      "--record FILE: at the end, the samples not answered (flexloop replay "
      "--controller-record).\n"
      "Example, inside one tools/netns-run -- bash:\n"
      "  flexloop build tools/scenes/metrology_frame_lqg.toml -o /tmp/lqg.json\n"
      "  flexloop-c-controller /tmp/lqg.json --duration 7 &\n"
      "  flexloop plant /tmp/lqg.json --duration 5 --cpu 0 --json /tmp/plant.json\n"
      "  (then: flexloop replay /tmp/lqg.json --plant-report /tmp/plant.json)\n"
      "Over iceoryx (no namespace needed: nothing leaves the host's shared memory):\n"
      "  flexloop roudi &\n"
      "  flexloop-c-controller /tmp/lqg.json --transport iceoryx --duration 7 &\n"
      "  flexloop plant /tmp/lqg.json --transport iceoryx --duration 5 --json /tmp/plant.json\n");
}

static int bad_argument(const char* argument) {
  fprintf(stderr, "flexloop-c-controller: unknown argument '%s' (see --help)\n", argument);
  return 2;
}

/* 0 when the options are read, else the exit code (0 after --help is -1). */
static int parse(int argc, char** argv, Options* o, Controller* c) {
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    const int has_value = i + 1 < argc;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage();
      return -1;
    } else if (strcmp(a, "--transport") == 0 && has_value) {
      const char* t = argv[++i];
      if (strcmp(t, "lcm") != 0 && strcmp(t, "iceoryx") != 0) {
        fprintf(stderr, "flexloop-c-controller: --transport is lcm or iceoryx (got %s)\n", t);
        return 2;
      }
      o->iceoryx = strcmp(t, "iceoryx") == 0;
    } else if (strcmp(a, "--url") == 0 && has_value) {
      o->url = argv[++i];
    } else if (strcmp(a, "--spin") == 0) {
      o->spin = 1;
    } else if (strcmp(a, "--duration") == 0 && has_value) {
      o->duration_s = atof(argv[++i]);
    } else if (strcmp(a, "--record") == 0 && has_value) {
      o->record = argv[++i];
    } else if (strcmp(a, "--safe-after") == 0 && has_value) {
      c->safe_after = atoll(argv[++i]);
    } else if (a[0] != '-' && !o->loop) {
      o->loop = a;
    } else {
      return bad_argument(a);
    }
  }
  if (!o->loop) {
    fprintf(stderr, "flexloop-c-controller: give a loop artefact (see --help)\n");
    return 2;
  }
  if (o->iceoryx && o->url) {
    fprintf(stderr, "flexloop-c-controller: --url is for --transport lcm\n");
    return 2;
  }
  return 0;
}

int main(int argc, char** argv) {
  Options o = {.url = NULL};
  static Controller c; /* static: its gap record is large */
  c.safe_after = 10;
  const int parsed = parse(argc, argv, &o, &c);
  if (parsed != 0) return parsed < 0 ? 0 : parsed;
  if (!flexloop_decode_sample_matches_lcm_gen()) {
    fprintf(stderr,
            "flexloop-c-controller: sample_decode.c does not follow "
            "msgs/sensor_sample_t.lcm (its fields changed): update it\n");
    return 2;
  }
  load(&c, o.loop);
  if (o.iceoryx) {
    c.carrier = flexloop_carrier_iceoryx_open(on_message, &c);
  } else {
    const char* url = o.url ? o.url : getenv("LCM_DEFAULT_URL");
    c.carrier =
        flexloop_carrier_lcm_open(url ? url : "udpm://239.255.76.67:7667?ttl=0", on_message, &c);
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  printf("flexloop-c-controller: %s, %d states, %d sensors -> %d actuators, %s%s\n", o.loop, c.nx,
         c.ns, c.nc, c.carrier->description, o.spin ? ", spinning" : "");
  fflush(stdout);
  const int64_t end = o.duration_s > 0 ? now_ns() + (int64_t)(o.duration_s * 1e9) : INT64_MAX;
  int failed = 0;
  while (!stop_requested && now_ns() < end && !failed)
    failed = c.carrier->receive(c.carrier, o.spin ? 0 : 100) < 0 && !stop_requested; /* EINTR */
  printf(
      "flexloop-c-controller: answered %lld samples (%lld messages not this loop's samples, "
      "%lld answers not sent)\n",
      (long long)c.answered, (long long)c.undecoded, (long long)c.unsent);
  c.carrier->close(c.carrier);
  if (failed) fprintf(stderr, "flexloop-c-controller: receiving failed\n");
  if (o.record && !write_record(&c, o.record)) {
    fprintf(stderr, "flexloop-c-controller: %s: cannot be written\n", o.record);
    return 1;
  }
  return failed ? 1 : 0;
}
