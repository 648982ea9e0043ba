/* parallel_for shim (brep/parallel_tbb.cpp): every index exactly once, any thread count. */
#include <stdlib.h>

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

int main(void)
{
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
