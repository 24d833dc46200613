// SPDX-License-Identifier: BSD-3-Clause
/* A shared library that is no FMU: loading it writes "<its own path>.loaded" (its constructor
 * runs in dlopen, before any function of it is called). tests/fmu places it where an FMU's
 * modelIdentifier would reach from outside the archive ("../../../../x", "/abs/x") and checks
 * that no marker appears: the loader refuses before dlopen. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char anchor = 0; /* an address inside this library, for dladdr */

__attribute__((constructor)) static void write_marker(void) {
  Dl_info self;
  if (!dladdr(&anchor, &self) || !self.dli_fname) return;
  char marker[4096];
  if (snprintf(marker, sizeof marker, "%s.loaded", self.dli_fname) >= (int)sizeof marker) return;
  FILE* f = fopen(marker, "w");
  if (!f) return;
  fputs("loaded\n", f);
  fclose(f);
}
