// SPDX-License-Identifier: BSD-3-Clause
/* A discrete state-space controller as an FMI 2.0 Co-Simulation FMU: flexloop's own law
 * (controller/runtime/state_space_controller.hpp) for a fixture FMU (issue 33), sized at compile
 * time (NX states, NS sensors, NC actuators; tools/fmu/CMakeLists.txt builds one FMU per size and
 * writes its modelDescription.xml). An FMU reads the sensors as they are, so this one removes the
 * held command's feedthrough itself, from the commands it answered (d: the feedthrough delay,
 * samples between a command and the measurement that first contains it beyond the loop's one):
 *
 *   f_k = y_k - D22 u_{k-1-d}
 *   v_k = E (C x_k + D f_k),   E = (I - D D22)^-1
 *   u_k = clamp(v_k, u_min, u_max)               per channel
 *   x_{k+1} = A x_k + B f_k + (B D22) u_k         (anti_windup = 1: x holds while a channel clamps)
 *
 * Parameters (row major, i, j from 1): A_i_j, B_i_j, C_i_j, D_i_j, D22_i_j, u_min_i, u_max_i,
 * anti_windup (0: none, 1: hold) and feedthrough_delay (d, 0 .. MAX_DELAY). Inputs y1..yNS,
 * outputs u1..uNC. fmi2ExitInitializationMode refuses (fmi2Error) I - D D22 singular, a non-finite
 * matrix entry, u_min > u_max, another anti_windup or feedthrough_delay. Value references in the
 * order above: y, u, A, B, C, D, D22, u_min, u_max, anti_windup, feedthrough_delay. The matrices
 * are the design at the loop's period; fmi2DoStep does not check h against it. Nothing is allocated
 * after fmi2Instantiate (the entry points that only store values are tools/fmu/fixture_fmu.h's). */
#include <math.h>
#include <string.h>

#include "common/fmi2.h"

#if !defined(NX) || !defined(NS) || !defined(NC) || !defined(FMU_GUID) || !defined(FMU_NAME)
#error "NX, NS, NC, FMU_GUID and FMU_NAME come from tools/fmu/CMakeLists.txt"
#endif
#if NS < 1 || NC < 1 || NX < 0
#error "a controller has a sensor and an actuator at least"
#endif

/* A zero-state design still needs arrays of positive size. */
#define NX1 (NX > 0 ? NX : 1)

#define VR_Y 0
#define VR_U (VR_Y + NS)
#define VR_A (VR_U + NC)
#define VR_B (VR_A + NX * NX)
#define VR_C (VR_B + NX * NS)
#define VR_D (VR_C + NC * NX)
#define VR_D22 (VR_D + NC * NS)
#define VR_UMIN (VR_D22 + NS * NC)
#define VR_UMAX (VR_UMIN + NC)
#define VR_AW (VR_UMAX + NC)
#define VR_DELAY (VR_AW + 1)
#define VR_COUNT (VR_DELAY + 1)
/* The longest feedthrough delay (flexloop's own, artefact/pi_parameters.hpp). */
#define MAX_DELAY 32
#define VR_OUTPUTS VR_U
#define VR_PARAMETERS VR_A

typedef struct {
  double values[VR_COUNT]; /* every variable by value reference; u: the command held */
  double EC[NC][NX1], ED[NC][NS], BD22[NX1][NC];
  double x[NX1];
  double sent[MAX_DELAY + 1][NC]; /* the commands answered, a ring: sent[head] the last */
  int head, delay, hold;
  int initialised;
  int failed; /* fmi2Error returned: only fmi2Reset, fmi2FreeInstance, fmi2GetReal now */
  const fmi2CallbackFunctions* callbacks;
} Instance;

#include "tools/fmu/fixture_fmu.h"

#define AT(vr, cols, i, j) in->values[(vr) + (i) * (cols) + (j)]

/* [EC, ED] = (I - D D22)^-1 [C, D]. 0 when I - D D22 is singular. */
static int solve_output(Instance* in) {
  double M[NC][NC], R[NC][NX + NS];
  for (int i = 0; i < NC; ++i) {
    for (int j = 0; j < NC; ++j) {
      double s = 0;
      for (int k = 0; k < NS; ++k) s += AT(VR_D, NS, i, k) * AT(VR_D22, NC, k, j);
      M[i][j] = (i == j ? 1.0 : 0.0) - s;
    }
    for (int j = 0; j < NX; ++j) R[i][j] = AT(VR_C, NX, i, j);
    for (int j = 0; j < NS; ++j) R[i][NX + j] = AT(VR_D, NS, i, j);
  }
  if (!gauss_jordan(NC, NX + NS, &M[0][0], &R[0][0])) return 0;
  for (int i = 0; i < NC; ++i) {
    for (int j = 0; j < NX; ++j) in->EC[i][j] = R[i][j];
    for (int j = 0; j < NS; ++j) in->ED[i][j] = R[i][NX + j];
  }
  return 1;
}

static void reset_state(Instance* in) {
  memset(in->values, 0, sizeof in->values);
  memset(in->x, 0, sizeof in->x);
  memset(in->sent, 0, sizeof in->sent);
  in->head = 0;
  for (int i = 0; i < NC; ++i) {
    in->values[VR_UMIN + i] = -INFINITY;
    in->values[VR_UMAX + i] = INFINITY;
  }
  in->initialised = 0;
}

static int initialise(Instance* in) {
  for (int r = VR_A; r < VR_UMIN; ++r)
    if (!isfinite(in->values[r])) {
      log_error(in, "a matrix entry is not finite");
      return 0;
    }
  for (int i = 0; i < NC; ++i)
    if (!(in->values[VR_UMIN + i] <= in->values[VR_UMAX + i])) {
      log_error(in, "u_min > u_max");
      return 0;
    }
  const double aw = in->values[VR_AW];
  if (aw != 0.0 && aw != 1.0) {
    log_error(in, "anti_windup must be 0 (none) or 1 (hold)");
    return 0;
  }
  if (!solve_output(in)) {
    log_error(in, "I - D D22 is singular: the loop through the sensors' feedthrough is ill-posed");
    return 0;
  }
  for (int i = 0; i < NX; ++i)
    for (int j = 0; j < NC; ++j) {
      double s = 0;
      for (int k = 0; k < NS; ++k) s += AT(VR_B, NS, i, k) * AT(VR_D22, NC, k, j);
      in->BD22[i][j] = s;
    }
  const double d = in->values[VR_DELAY];
  if (!(d >= 0 && d <= MAX_DELAY && d == floor(d))) {
    log_error(in, "feedthrough_delay must be a whole number of samples, 0 .. 32");
    return 0;
  }
  in->hold = aw == 1.0;
  in->delay = (int)d;
  return 1;
}

static fmi2Status step(Instance* in, double h) {
  (void)h;
  const double* y = &in->values[VR_Y];
  double* u = &in->values[VR_U];
  const double* held = in->sent[(in->head - in->delay + MAX_DELAY + 1) % (MAX_DELAY + 1)];
  const double *lo = &in->values[VR_UMIN], *hi = &in->values[VR_UMAX];
  double f[NS], v[NC], x_next[NX1];
  for (int i = 0; i < NS; ++i) {
    double s = 0;
    for (int j = 0; j < NC; ++j) s += AT(VR_D22, NC, i, j) * held[j];
    f[i] = y[i] - s;
  }
  for (int i = 0; i < NC; ++i) {
    double s = 0;
    for (int j = 0; j < NX; ++j) s += in->EC[i][j] * in->x[j];
    for (int j = 0; j < NS; ++j) s += in->ED[i][j] * f[j];
    v[i] = s;
  }
  int clamped = 0;
  for (int i = 0; i < NC; ++i) { /* as std::min(std::max(v, lo), hi) */
    const double m = v[i] < lo[i] ? lo[i] : v[i];
    u[i] = hi[i] < m ? hi[i] : m;
    clamped |= u[i] != v[i];
  }
  if (NX > 0 && !(clamped && in->hold)) {
    for (int i = 0; i < NX; ++i) {
      double s = 0;
      for (int j = 0; j < NX; ++j) s += AT(VR_A, NX, i, j) * in->x[j];
      for (int j = 0; j < NS; ++j) s += AT(VR_B, NS, i, j) * f[j];
      for (int j = 0; j < NC; ++j) s += in->BD22[i][j] * u[j];
      x_next[i] = s;
    }
    memcpy(in->x, x_next, sizeof(double) * NX);
  }
  in->head = (in->head + 1) % (MAX_DELAY + 1);
  memcpy(in->sent[in->head], u, sizeof(double) * NC);
  return fmi2OK;
}
