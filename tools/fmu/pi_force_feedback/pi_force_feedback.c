/* The metrology frame's PI force feedback (controller/runtime/pi_controller.hpp has the law) as an
 * FMI 2.0 Co-Simulation FMU: the project's own fixture for the FMU loop (issue 33). Six channels,
 * force sensors in series with the actuators (D22 = I, no extra delay). Parameters: the full
 * gains K_P_i_j, K_I_i_j (i, j = 1..6), the leak leak_rad_s, the limits u_min, u_max and the
 * sensors' range y_max (a measured force beyond it is an overload: fmi2DoStep refuses to act on
 * it and returns fmi2Error, as a deployed controller would stop). Inputs
 * y1..y6 (measured forces), outputs u1..u6 (commands). fmi2DoStep(t, h) takes the inputs set at
 * t and gives the command held from t on (a sampled controller with direct feedthrough):
 *
 *   f = y - u_prev,  v = G_f f + s,  u = clamp(v),  s += u - v,  s = a s + b G_x (f + u)
 *   G_f = -E K_P,  G_x = -E K_I,  E = (I + K_P)^-1,  a = exp(-w_l h),  b = (1 - a) / w_l or h
 *
 * Value references: 0..5 y, 6..11 u, 12..47 K_P (row major), 48..83 K_I, 84 leak_rad_s,
 * 85 u_min, 86 u_max, 87 y_max (modelDescription.xml lists them). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "controller/fmu/fmi2.h"

#define N 6
#define VR_Y 0
#define VR_U (VR_Y + N)
#define VR_KP (VR_U + N)
#define VR_KI (VR_KP + N * N)
#define VR_LEAK (VR_KI + N * N)
#define VR_UMIN (VR_LEAK + 1)
#define VR_UMAX (VR_UMIN + 1)
#define VR_YMAX (VR_UMAX + 1)
#define VR_COUNT (VR_YMAX + 1)

#define EXPORT __attribute__((visibility("default")))

typedef struct {
  double values[VR_COUNT]; /* every variable by value reference */
  double G_f[N][N], G_x[N][N];
  double s[N];    /* the integral command G_x x */
  double h_gains; /* the step size a and b were computed for (0: not yet) */
  double a, b;
  int initialised;
  const fmi2CallbackFunctions* callbacks;
} Instance;

static void log_error(Instance* in, const char* message) {
  if (in->callbacks && in->callbacks->logger)
    in->callbacks->logger(in->callbacks->componentEnvironment, "pi_force_feedback", fmi2Error,
                          "logStatusError", "%s", message);
}

/* X = -(I + K_P)^-1 M by Gauss-Jordan elimination with partial pivoting. 0 when singular. */
static int solve_gains(const double* K_P, const double* M, double X[N][N]) {
  double A[N][N], B[N][N];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      A[i][j] = K_P[i * N + j] + (i == j ? 1.0 : 0.0);
      B[i][j] = -M[i * N + j];
    }
  for (int k = 0; k < N; ++k) {
    int p = k;
    for (int i = k + 1; i < N; ++i)
      if (fabs(A[i][k]) > fabs(A[p][k])) p = i;
    if (A[p][k] == 0.0) return 0;
    for (int j = 0; j < N; ++j) {
      double t = A[k][j];
      A[k][j] = A[p][j];
      A[p][j] = t;
      t = B[k][j];
      B[k][j] = B[p][j];
      B[p][j] = t;
    }
    for (int i = 0; i < N; ++i) {
      if (i == k) continue;
      const double m = A[i][k] / A[k][k];
      for (int j = 0; j < N; ++j) {
        A[i][j] -= m * A[k][j];
        B[i][j] -= m * B[k][j];
      }
    }
  }
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) X[i][j] = B[i][j] / A[i][i];
  return 1;
}

static void reset_state(Instance* in) {
  memset(in->values, 0, sizeof in->values);
  memset(in->s, 0, sizeof in->s);
  in->values[VR_UMIN] = -INFINITY;
  in->values[VR_UMAX] = INFINITY;
  in->values[VR_YMAX] = INFINITY;
  in->h_gains = 0;
  in->initialised = 0;
}

EXPORT const char* fmi2GetTypesPlatform(void) {
  return "default";
}
EXPORT const char* fmi2GetVersion(void) {
  return "2.0";
}

EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                      const fmi2String categories[]) {
  (void)c, (void)on, (void)n, (void)categories;
  return fmi2OK;
}

EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                     fmi2String resources, const fmi2CallbackFunctions* callbacks,
                                     fmi2Boolean visible, fmi2Boolean logging) {
  (void)name, (void)resources, (void)visible, (void)logging;
  if (type != fmi2CoSimulation || !guid ||
      strcmp(guid, "{5f1d8c2e-33a0-4b6e-9d1c-pi-force-feedback-1}") != 0)
    return NULL;
  Instance* in = calloc(1, sizeof *in);
  if (!in) return NULL;
  in->callbacks = callbacks;
  reset_state(in);
  return in;
}

EXPORT void fmi2FreeInstance(fmi2Component c) {
  free(c);
}

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)c, (void)tol_defined, (void)tol, (void)start, (void)stop_defined, (void)stop;
  return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  (void)c;
  return fmi2OK;
}

EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  Instance* in = c;
  if (!solve_gains(&in->values[VR_KP], &in->values[VR_KP], in->G_f) ||
      !solve_gains(&in->values[VR_KP], &in->values[VR_KI], in->G_x)) {
    log_error(in, "I + K_P is singular");
    return fmi2Error;
  }
  if (!(in->values[VR_LEAK] >= 0) || !(in->values[VR_UMIN] <= in->values[VR_UMAX])) {
    log_error(in, "leak_rad_s < 0 or u_min > u_max");
    return fmi2Error;
  }
  in->initialised = 1;
  return fmi2OK;
}

EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
  (void)c;
  return fmi2OK;
}

EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  reset_state(c);
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  Instance* in = c;
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] >= VR_COUNT) return fmi2Error;
    value[i] = in->values[vr[i]];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  Instance* in = c;
  for (size_t i = 0; i < n; ++i) {
    /* Parameters are fixed once initialised; the commands are outputs. */
    if (vr[i] >= VR_COUNT || (vr[i] >= VR_U && vr[i] < VR_KP) ||
        (in->initialised && vr[i] >= VR_KP))
      return fmi2Error;
    in->values[vr[i]] = value[i];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set_prior) {
  (void)t, (void)no_set_prior;
  Instance* in = c;
  if (!in->initialised || !(h > 0)) return fmi2Error;
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
      return fmi2Error;
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
