/* parallel.h — a C interface to data-parallel loops (implemented over oneTBB).
 *
 * Work is cut into chunks of consecutive indices; the body is called on disjoint half-open
 * ranges [begin, end) that together cover [0, n) exactly once. Bodies must not throw, must not
 * call exit, and must write only to data indexed by their own range (or synchronise). A result
 * that must not depend on the thread count should be combined by index, never by arrival. */
#ifndef CB_PARALLEL_H
#define CB_PARALLEL_H

#include <stddef.h>

#include "brep/status.h"

typedef void (*cb_parallel_body)(void *ctx, size_t begin, size_t end);

/* Runs body over [0, n) in chunks of at least `grain` indices (0 means 1) on at most
 * `threads` threads (0: all hardware threads; 1: the calling thread alone, in index order).
 * Returns CB_ERR_NOMEM if the task scheduler failed for lack of resources; the body may then
 * have run on part of the range only. */
cb_status cb_parallel_for(size_t n, size_t grain, int threads, cb_parallel_body body, void *ctx);

/* Number of hardware threads the scheduler would use for threads = 0. */
int cb_parallel_max_threads(void);

#endif
