/* parallel_for shim (brep/parallel_tbb.cpp): every index exactly once, any thread count. */
#include <stdlib.h>

#include "brep/context.h"
#include "brep/parallel.h"
#include "check.h"

typedef struct {
    int *hits;
    double *out;
    size_t max_chunk, min_chunk;
    size_t last_end; /* for the in-order check with one thread */
    int in_order;
} loop_ctx;

static void body(void *p, size_t begin, size_t end)
{
    loop_ctx *c = p;
    for (size_t i = begin; i < end; i++) {
        c->hits[i]++;
        c->out[i] = (double)i * (double)i;
    }
}

static void ordered_body(void *p, size_t begin, size_t end)
{
    loop_ctx *c = p;
    if (begin != c->last_end)
        c->in_order = 0;
    c->last_end = end;
    body(p, begin, end);
}

/* Progress through a context from every worker: the callback sees a non-decreasing sequence
 * ending at 1; after cb_context_cancel every worker sees the flag. */
typedef struct {
    cb_context *ctx;
    size_t n;
    int done; /* atomic counter of finished indices */
    int skipped;
} progress_loop;

typedef struct {
    double last;
    int calls, decreasing;
} progress_seen;

static void seen_progress(void *user, double f, const char *stage)
{
    progress_seen *s = user;
    (void)stage;
    if (f < s->last)
        s->decreasing++;
    s->last = f;
    s->calls++;
}

static void progress_body(void *p, size_t begin, size_t end)
{
    progress_loop *c = p;
    for (size_t i = begin; i < end; i++) {
        if (cb_context_cancelled(c->ctx)) {
            __atomic_add_fetch(&c->skipped, 1, __ATOMIC_RELAXED);
            continue;
        }
        int d = __atomic_add_fetch(&c->done, 1, __ATOMIC_RELAXED);
        cb_context_progress(c->ctx, d, (double)c->n, "test");
    }
}

static void check_context(void)
{
    CHECK(!cb_context_cancelled(NULL) && cb_context_threads(NULL) == 0, "NULL context defaults");
    cb_context_progress(NULL, 1, 2, "none");
    cb_context_cancel(NULL);
    for (int th = 1; th <= 2; th++) {
        cb_context ctx;
        cb_context_init(&ctx);
        ctx.threads = th;
        progress_seen seen = {-1.0, 0, 0};
        ctx.progress = seen_progress;
        ctx.user = &seen;
        progress_loop c = {&ctx, 20000, 0, 0};
        CHECK(cb_parallel_for(c.n, 16, th, progress_body, &c) == CB_OK, "threads %d", th);
        CHECK(seen.decreasing == 0 && seen.last == 1.0 && seen.calls >= 1,
              "threads %d: %d calls, %d decreasing, last %g", th, seen.calls, seen.decreasing,
              seen.last);
        CHECK(!cb_context_cancelled(&ctx), "threads %d: not cancelled", th);
        cb_context_cancel(&ctx);
        CHECK(cb_context_cancelled(&ctx), "threads %d: cancelled", th);
        c.done = 0;
        CHECK(cb_parallel_for(c.n, 16, th, progress_body, &c) == CB_OK, "threads %d", th);
        CHECK(c.done == 0 && c.skipped == (int)c.n, "threads %d: %d ran after cancel", th,
              c.done);
        cb_context_progress_reset(&ctx);
        cb_context_progress(&ctx, 0, 1, "again");
        CHECK(seen.last == 0.0, "threads %d: reset lets progress start at 0 (%g)", th, seen.last);
    }
}

int main(void)
{
    check_context();
    static const size_t sizes[] = {0, 1, 7, 1000, 123457};
    static const size_t grains[] = {0, 1, 13, 5000};
    static const int threads[] = {0, 1, 2, 3};
    for (size_t a = 0; a < sizeof sizes / sizeof *sizes; a++)
        for (size_t b = 0; b < sizeof grains / sizeof *grains; b++)
            for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
                size_t n = sizes[a];
                loop_ctx c = {calloc(n + 1, sizeof(int)), calloc(n + 1, sizeof(double)), 0, 0,
                              0, 1};
                int th = threads[t];
                cb_status st =
                    cb_parallel_for(n, grains[b], th, th == 1 ? ordered_body : body, &c);
                CHECK(st == CB_OK, "n=%zu grain=%zu threads=%d: status %d", n, grains[b], th, st);
                size_t bad = 0;
                for (size_t i = 0; i < n; i++)
                    bad += c.hits[i] != 1 || c.out[i] != (double)i * (double)i;
                CHECK(bad == 0, "n=%zu grain=%zu threads=%d: %zu indices not visited once", n,
                      grains[b], th, bad);
                if (th == 1)
                    CHECK(c.in_order && c.last_end == n,
                          "n=%zu grain=%zu: one thread must run in index order", n, grains[b]);
                free(c.hits);
                free(c.out);
            }
    CHECK(cb_parallel_max_threads() >= 1, "max threads %d", cb_parallel_max_threads());
    return check_report("parallel");
}
