// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// OpenBLAS's worker threads spin while they wait: a command that calls LAPACK on the small and
// middling matrices of a loop (a campaign's samples, sim's and hil's set-up) beside other busy
// processes gets slower with them, not faster (a campaign on 2 cores: 193 000 sched_yield calls
// for 200 samples; one thread per worker doubled its rate). So `flexloop` runs its BLAS on one
// thread, whatever OPENBLAS_NUM_THREADS says, unless FLEXLOOP_BLAS_THREADS names a count (a
// 10^5-DOF model's dense factorisations alone on a machine may want more). A BLAS other than
// OpenBLAS (no openblas_set_num_threads) is left as it is. One thread also makes the results
// the same to the bit whatever the user's OPENBLAS_NUM_THREADS (2 threads round a campaign's
// nominal figures differently).
namespace flexloop::cli {

/// Sets the BLAS thread count (see above); returns the count set, 0 when the BLAS is not OpenBLAS.
int set_blas_threads();

}  // namespace flexloop::cli
