// SPDX-License-Identifier: BSD-3-Clause
/* The metrology frame's PI force feedback (controller/runtime/pi_controller.hpp has the law) as an
 * FMI 2.0 Co-Simulation FMU: the project's own fixture for the FMU loop (issue 33). Six channels,
 * force sensors in series with the actuators (D22 = I, no extra delay). Parameters: the full
 * gains K_P_i_j, K_I_i_j (i, j = 1..6), the leak leak_rad_s, the limits u_min, u_max and the
 * sensors' range y_max (a measured force beyond it is an overload: fmi2DoStep refuses to act on
 * it and returns fmi2Error, as a deployed controller would stop) and allocations_per_step (that
 * many malloc/free pairs in each fmi2DoStep: a controller that breaks the promise of no
 * allocation in a step, for the tests of the controller process's count). Inputs
 * y1..y6 (measured forces), outputs u1..u6 (commands). fmi2DoStep(t, h) takes the inputs set at
 * t and gives the command held from t on (a sampled controller with direct feedthrough):
 *
 *   f = y - u_prev,  v = G_f f + s,  u = clamp(v),  s += u - v,  s = a s + b G_x (f + u)
 *   G_f = -E K_P,  G_x = -E K_I,  E = (I + K_P)^-1,  a = exp(-w_l h),  b = (1 - a) / w_l or h
 *
 * Value references: 0..5 y, 6..11 u, 12..47 K_P (row major), 48..83 K_I, 84 leak_rad_s,
 * 85 u_min, 86 u_max, 87 y_max, 88 allocations_per_step, 89 fatal_on_overload (an overload is
 * fmi2Fatal instead of fmi2Error when not 0), 90 step_status and 91 status_at_step (one step
 * answered with another status, or a crash: tools/fmu/fixture_fmu.h), and the outputs
 * 92 reset_calls, 93 setup_calls (the instance's fmi2Reset and fmi2SetupExperiment calls)
 * (modelDescription.xml lists them). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/fmi2.h"

#define FMU_NAME "pi_force_feedback"
#define FMU_GUID "{5f1d8c2e-33a0-4b6e-9d1c-pi-force-feedback-1}"

#define N 6
#define VR_Y 0
#define VR_U (VR_Y + N)
#define VR_KP (VR_U + N)
#define VR_KI (VR_KP + N * N)
#define VR_LEAK (VR_KI + N * N)
#define VR_UMIN (VR_LEAK + 1)
#define VR_UMAX (VR_UMIN + 1)
#define VR_YMAX (VR_UMAX + 1)
#define VR_ALLOCATIONS (VR_YMAX + 1)
#define VR_FATAL (VR_ALLOCATIONS + 1)
#define VR_STEP_STATUS (VR_FATAL + 1)
#define VR_STATUS_AT_STEP (VR_STEP_STATUS + 1)
#define VR_RESET_CALLS (VR_STATUS_AT_STEP + 1)
#define VR_SETUP_CALLS (VR_RESET_CALLS + 1)
#define VR_COUNT (VR_SETUP_CALLS + 1)
#define VR_OUTPUTS VR_U
#define VR_PARAMETERS VR_KP

typedef struct {
  double values[VR_COUNT]; /* every variable by value reference */
  double G_f[N][N], G_x[N][N];
  double s[N];    /* the integral command G_x x */
  double h_gains; /* the step size a and b were computed for (0: not yet) */
  double a, b;
  int initialised;
  int failed; /* fmi2Error returned: only fmi2Reset, fmi2FreeInstance, fmi2GetReal now */
  const fmi2CallbackFunctions* callbacks;
} Instance;

#include "tools/fmu/fixture_fmu.h"

/* X = -(I + K_P)^-1 M. 0 when singular. */
static int solve_gains(const double* K_P, const double* M, double X[N][N]) {
  double A[N][N];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      A[i][j] = K_P[i * N + j] + (i == j ? 1.0 : 0.0);
      X[i][j] = -M[i * N + j];
    }
  return gauss_jordan(N, N, &A[0][0], &X[0][0]);
}

static void reset_state(Instance* in) {
  memset(in->values, 0, sizeof in->values);
  memset(in->s, 0, sizeof in->s);
  in->values[VR_UMIN] = -INFINITY;
  in->values[VR_UMAX] = INFINITY;
  in->values[VR_YMAX] = INFINITY;
  in->values[VR_STATUS_AT_STEP] = -1;
  in->values[VR_RESET_CALLS] = fixture_calls(in)->reset_calls;
  in->values[VR_SETUP_CALLS] = fixture_calls(in)->setup_calls;
  in->h_gains = 0;
  in->initialised = 0;
}

static int initialise(Instance* in) {
  if (!solve_gains(&in->values[VR_KP], &in->values[VR_KP], in->G_f) ||
      !solve_gains(&in->values[VR_KP], &in->values[VR_KI], in->G_x)) {
    log_error(in, "I + K_P is singular");
    return 0;
  }
  if (!(in->values[VR_LEAK] >= 0) || !(in->values[VR_UMIN] <= in->values[VR_UMAX])) {
    log_error(in, "leak_rad_s < 0 or u_min > u_max");
    return 0;
  }
  return 1;
}

static fmi2Status step(Instance* in, double h) {
  if (h != in->h_gains) { /* the leak's discrete form for this step size */
    const double w = in->values[VR_LEAK];
    in->a = exp(-w * h);
    in->b = w > 0 ? (1.0 - in->a) / w : h;
    in->h_gains = h;
  }
  double* y = &in->values[VR_Y];
  double* u = &in->values[VR_U];
  const double lo = in->values[VR_UMIN], hi = in->values[VR_UMAX];
  double f[N], v[N];
  for (int i = 0; i < N; ++i)
    if (!(fabs(y[i]) <= in->values[VR_YMAX])) {
      log_error(in, "a measured force is beyond the sensors' range y_max");
      return in->values[VR_FATAL] != 0 ? fmi2Fatal : fmi2Error;
    }
  for (int i = 0; i < (int)in->values[VR_ALLOCATIONS]; ++i) {
    static void* volatile allocated; /* volatile: the pair is not optimised away */
    allocated = malloc(64);
    free(allocated);
  }
  for (int i = 0; i < N; ++i) f[i] = y[i] - u[i]; /* u: the command held until now */
  for (int i = 0; i < N; ++i) {
    double p = 0;
    for (int j = 0; j < N; ++j) p += in->G_f[i][j] * f[j];
    v[i] = p + in->s[i];
  }
  for (int i = 0; i < N; ++i) {
    u[i] = fmin(fmax(v[i], lo), hi);
    in->s[i] += u[i] - v[i];
    f[i] += u[i];
  }
  for (int i = 0; i < N; ++i) {
    double g = 0;
    for (int j = 0; j < N; ++j) g += in->G_x[i][j] * f[j];
    in->s[i] = in->a * in->s[i] + in->b * g;
  }
  return fmi2OK;
}
