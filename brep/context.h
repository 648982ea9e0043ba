/* context.h — the execution context of long operations: thread count, progress report and
 * cancellation.
 *
 * A long operation (tessellation, mass properties, SSI over many pairs, a Boolean) takes a
 * `cb_context *` that may be NULL (all threads, no progress, never cancelled). The caller owns
 * the context; it must outlive the call. Another thread, or the progress callback itself, may
 * ask the operation to stop with cb_context_cancel: the operation checks the flag in its long
 * loops, frees what it made and returns CB_ERR_CANCELLED. */
#ifndef CB_CONTEXT_H
#define CB_CONTEXT_H

#include "brep/status.h"

/* Called with a fraction of the work done in [0, 1], never decreasing within one operation,
 * and the name of the stage running ("tessellate", ...). Calls never overlap (they are
 * serialised even when the work runs on several threads), but may come from a worker thread.
 * The callback may cancel (cb_context_cancel) but must not report progress itself. */
typedef void (*cb_progress_fn)(void *user, double fraction, const char *stage);

typedef struct {
    int threads;             /* at most this many threads (0: all hardware threads, 1: serial) */
    cb_progress_fn progress; /* NULL: no report */
    void *user;              /* passed to progress */
    int cancel_flag;         /* read and written through the functions below only */
    int lock;                /* serialises progress calls */
    double last_fraction;    /* largest fraction reported so far */
} cb_context;

/* threads = 0, no progress callback, not cancelled. */
void cb_context_init(cb_context *ctx);

/* Asks the running operation to stop (thread safe; idempotent). */
void cb_context_cancel(cb_context *ctx);

/* Non-zero once cb_context_cancel was called; 0 for a NULL context. Thread safe. */
int cb_context_cancelled(const cb_context *ctx);

/* Threads to use: ctx->threads, or 0 (all) for a NULL context. */
int cb_context_threads(const cb_context *ctx);

/* Forgets the fractions reported so far, so the next operation may start from 0 again. */
void cb_context_progress_reset(cb_context *ctx);

/* Reports done / total of the stage (total > 0); the callback is called only when the fraction
 * exceeds every fraction reported before, so it never decreases. No-op for a NULL context or
 * callback. Thread safe. */
void cb_context_progress(cb_context *ctx, double done, double total, const char *stage);

#endif
