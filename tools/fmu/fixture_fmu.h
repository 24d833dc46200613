// SPDX-License-Identifier: BSD-3-Clause
#ifndef FLEXLOOP_TOOLS_FMU_FIXTURE_FMU_H
#define FLEXLOOP_TOOLS_FMU_FIXTURE_FMU_H
/* What the project's fixture FMUs (tools/fmu) share: the FMI 2.0 entry points that only store
 * values (every variable a real, kept in `values` by value reference), the error logger and a
 * small linear solve. Included once by each fixture's C file, after it has defined FMU_NAME,
 * FMU_GUID, VR_OUTPUTS (the first output's value reference; inputs come before it), VR_PARAMETERS
 * (the first parameter's; outputs before it), VR_COUNT and the type Instance (at least
 * `double values[VR_COUNT]`, `int initialised`, `const fmi2CallbackFunctions* callbacks`). The
 * fixture defines its law: reset_state (at instantiation and fmi2Reset), initialise (at
 * fmi2ExitInitializationMode: 0 refuses the parameters, after log_error) and step (fmi2DoStep,
 * once initialised, h > 0). Nothing here allocates but fmi2Instantiate.
 *
 * The fixtures hold their importer to FMI 2.0's state machine and abort the process on a call
 * it does not allow, so that a test passing shows none was made: no call at all after a call
 * returned fmi2Fatal (the standard: "it is not possible to call any other function for any of the
 * FMU instances"), after fmi2Error only fmi2Reset, fmi2FreeInstance and fmi2GetReal, and
 * fmi2Terminate only once initialised. Instance also needs `int failed` (fmi2Error seen).
 * fmi2Discard counts as fmi2Error here (then fmi2GetBooleanStatus(fmi2Terminated) and
 * fmi2GetRealStatus(fmi2LastSuccessfulTime) answer too); after fmi2Pending only fmi2FreeInstance.
 *
 * A fixture that defines VR_STEP_STATUS and VR_STATUS_AT_STEP (two parameters) answers one
 * fmi2DoStep, the one of that index since initialisation (from 0), with the status it names:
 * 1 fmi2Warning (the step done, a warning logged), 2 fmi2Discard, 5 fmi2Pending (the step not
 * done), 11 the process killed by SIGSEGV (a controller that crashes); 0 none. One that defines
 * VR_RESET_CALLS and VR_SETUP_CALLS (two outputs) counts there the instance's fmi2Reset and
 * fmi2SetupExperiment calls since fmi2Instantiate (restored by its reset_state from
 * fixture_calls(in)). */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/fmi2.h"

#define EXPORT __attribute__((visibility("default")))

static void reset_state(Instance* in);
static int initialise(Instance* in);
static fmi2Status step(Instance* in, double h);

static int fixture_fatal; /* an fmi2Fatal was returned: every instance is corrupted */

/* What the shared entry points keep of an instance beside the fixture's own Instance (which comes
 * first, so that an Instance* is a Tracked*). */
typedef struct {
  Instance in;
  long steps;         /* fmi2DoStep calls since initialisation */
  double last_time;   /* the end of the last step completed */
  int pending;        /* fmi2Pending returned: only fmi2FreeInstance now */
  double reset_calls; /* fmi2Reset calls since fmi2Instantiate */
  double setup_calls; /* fmi2SetupExperiment calls since fmi2Instantiate */
} Tracked;

static Tracked* fixture_calls(Instance* in) {
  return (Tracked*)in;
}

/* Aborts on a call the state machine does not allow (see the top). */
static void require_allowed(const Instance* in, const char* call, int allowed_after_error) {
  if (in && fixture_calls((Instance*)in)->pending && strcmp(call, "fmi2FreeInstance") != 0) {
    fprintf(stderr, "fixture FMU %s: %s called after fmi2Pending: FMI 2.0 does not allow it\n",
            FMU_NAME, call);
    abort();
  }
  if (fixture_fatal || (in && in->failed && !allowed_after_error)) {
    fprintf(stderr, "fixture FMU %s: %s called after %s: FMI 2.0 does not allow it\n", FMU_NAME,
            call, fixture_fatal ? "fmi2Fatal" : "fmi2Error");
    abort();
  }
}

/* A status returned to the importer, remembered for require_allowed. */
static fmi2Status returned(Instance* in, fmi2Status status) {
  if (status == fmi2Error || status == fmi2Discard) in->failed = 1;
  if (status == fmi2Pending) fixture_calls(in)->pending = 1;
  if (status == fmi2Fatal) fixture_fatal = 1;
  return status;
}

static void log_error(Instance* in, const char* message) {
  if (in->callbacks && in->callbacks->logger)
    in->callbacks->logger(in->callbacks->componentEnvironment, FMU_NAME, fmi2Error,
                          "logStatusError", "%s", message);
}

/* Solves M X = R by Gauss-Jordan elimination with partial pivoting, both row major: M (n x n) is
 * overwritten, R (n x m) becomes X. 0 when M is singular (a zero pivot). */
static int gauss_jordan(int n, int m, double* M, double* R) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (fabs(M[i * n + k]) > fabs(M[p * n + k])) p = i;
    if (M[p * n + k] == 0.0) return 0;
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
    for (int i = 0; i < n; ++i) {
      if (i == k) continue;
      const double f = M[i * n + k] / M[k * n + k];
      for (int j = 0; j < n; ++j) M[i * n + j] -= f * M[k * n + j];
      for (int j = 0; j < m; ++j) R[i * m + j] -= f * R[k * m + j];
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) R[i * m + j] /= M[i * n + i];
  return 1;
}

/* The standard's values; tools/fmu/CMakeLists.txt builds the PI fixture with others, for the
 * loader's refusal of them (tests/fmu/test_fmu_description.cpp). */
#ifndef FMU_TYPES_PLATFORM
#define FMU_TYPES_PLATFORM "default"
#endif
#ifndef FMU_VERSION
#define FMU_VERSION "2.0"
#endif
EXPORT const char* fmi2GetTypesPlatform(void) {
  return FMU_TYPES_PLATFORM;
}
EXPORT const char* fmi2GetVersion(void) {
  return FMU_VERSION;
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
  require_allowed(NULL, "fmi2Instantiate", 0);
  if (type != fmi2CoSimulation || !guid || strcmp(guid, FMU_GUID) != 0) return NULL;
  Instance* in = calloc(1, sizeof(Tracked));
  if (!in) return NULL;
  in->callbacks = callbacks;
  reset_state(in);
  return in;
}

EXPORT void fmi2FreeInstance(fmi2Component c) {
  require_allowed(c, "fmi2FreeInstance", 1);
  free(c);
}

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_defined, fmi2Real stop) {
  (void)tol_defined, (void)tol, (void)start, (void)stop_defined, (void)stop;
  require_allowed(c, "fmi2SetupExperiment", 0);
  fixture_calls(c)->setup_calls += 1;
#ifdef VR_SETUP_CALLS
  ((Instance*)c)->values[VR_SETUP_CALLS] = fixture_calls(c)->setup_calls;
#endif
  return fmi2OK;
}

EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  require_allowed(c, "fmi2EnterInitializationMode", 0);
  return fmi2OK;
}

EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  Instance* in = c;
  require_allowed(in, "fmi2ExitInitializationMode", 0);
  if (!initialise(in)) return returned(in, fmi2Error);
  in->initialised = 1;
  fixture_calls(in)->steps = 0;
  return fmi2OK;
}

#ifdef VR_STEP_STATUS
/* The status the parameters ask of step n (see the top); fmi2OK for any other step. */
static fmi2Status asked_status(Instance* in, long n) {
  if ((double)n != in->values[VR_STATUS_AT_STEP]) return fmi2OK;
  const int asked = (int)in->values[VR_STEP_STATUS];
  if (asked == 11) raise(SIGSEGV);
  return asked == 1 ? fmi2Warning : asked == 2 ? fmi2Discard : asked == 5 ? fmi2Pending : fmi2OK;
}
#endif

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_set_prior) {
  (void)t, (void)no_set_prior;
  Instance* in = c;
  require_allowed(in, "fmi2DoStep", 0);
  if (!in->initialised || !(h > 0)) return returned(in, fmi2Error);
  Tracked* tr = fixture_calls(in);
  const long n = tr->steps++;
  fmi2Status asked = fmi2OK;
#ifdef VR_STEP_STATUS
  asked = asked_status(in, n);
  if (asked == fmi2Discard || asked == fmi2Pending) return returned(in, asked);
#endif
  fmi2Status status = step(in, h);
  if (status == fmi2OK && asked == fmi2Warning) {
    if (in->callbacks && in->callbacks->logger)
      in->callbacks->logger(in->callbacks->componentEnvironment, FMU_NAME, fmi2Warning,
                            "logStatusWarning", "step %ld warned as its parameters asked", n);
    status = fmi2Warning;
  }
  if (status == fmi2OK || status == fmi2Warning) tr->last_time = t + h;
  return returned(in, status);
}

EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s,
                                       fmi2Boolean* value) {
  require_allowed(c, "fmi2GetBooleanStatus", 1);
  if (s != fmi2Terminated) return fmi2Discard; /* FMI 2.0: a status it does not give */
  *value = ((Instance*)c)->failed ? fmi2True : fmi2False;
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  require_allowed(c, "fmi2GetRealStatus", 1);
  if (s != fmi2LastSuccessfulTime) return fmi2Discard;
  *value = fixture_calls(c)->last_time;
  return fmi2OK;
}

EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
  Instance* in = c;
  require_allowed(in, "fmi2Terminate", 0);
  if (!in->initialised) {
    fprintf(stderr, "fixture FMU %s: fmi2Terminate before initialisation ended\n", FMU_NAME);
    abort();
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2Reset(fmi2Component c) {
  require_allowed(c, "fmi2Reset", 1);
  fixture_calls(c)->reset_calls += 1;
  fixture_calls(c)->steps = 0;
  fixture_calls(c)->last_time = 0;
  reset_state(c); /* back to the instantiated state: the error is gone */
  ((Instance*)c)->failed = 0;
  return fmi2OK;
}

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
  Instance* in = c;
  require_allowed(in, "fmi2GetReal", 1);
  for (size_t i = 0; i < n; ++i) {
    if (vr[i] >= VR_COUNT) return returned(in, fmi2Error);
    value[i] = in->values[vr[i]];
  }
  return fmi2OK;
}

EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
  Instance* in = c;
  require_allowed(in, "fmi2SetReal", 0);
  for (size_t i = 0; i < n; ++i) {
    /* Parameters are fixed once initialised; the outputs are the FMU's own. */
    if (vr[i] >= VR_COUNT || (vr[i] >= VR_OUTPUTS && vr[i] < VR_PARAMETERS) ||
        (in->initialised && vr[i] >= VR_PARAMETERS))
      return returned(in, fmi2Error);
    in->values[vr[i]] = value[i];
  }
  return fmi2OK;
}

#endif
