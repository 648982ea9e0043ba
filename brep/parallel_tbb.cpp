// oneTBB behind the C interface of parallel.h. No C++ type or exception crosses it.
extern "C" {
#include "brep/parallel.h"
}

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

extern "C" cb_status cb_parallel_for(size_t n, size_t grain, int threads, cb_parallel_body body,
                                     void *ctx)
{
    if (n == 0)
        return CB_OK;
    if (grain == 0)
        grain = 1;
    if (threads == 1) {
        for (size_t b = 0; b < n; b += grain)
            body(ctx, b, b + grain < n ? b + grain : n);
        return CB_OK;
    }
    // More threads than the hardware offers only makes oneTBB warn and ignore the request.
    int hw = tbb::info::default_concurrency();
    if (threads <= 0 || threads > hw)
        threads = hw;
    try {
        tbb::task_arena arena(threads);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                              [&](const tbb::blocked_range<size_t> &r) {
                                  body(ctx, r.begin(), r.end());
                              });
        });
    } catch (...) {
        return CB_ERR_NOMEM;
    }
    return CB_OK;
}

extern "C" int cb_parallel_max_threads(void)
{
    return tbb::info::default_concurrency();
}
