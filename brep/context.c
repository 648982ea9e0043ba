#include "brep/context.h"

#include <stddef.h>

void cb_context_init(cb_context *ctx)
{
    ctx->threads = 0;
    ctx->progress = NULL;
    ctx->user = NULL;
    ctx->cancel_flag = 0;
    ctx->lock = 0;
    ctx->last_fraction = -1.0;
}

void cb_context_cancel(cb_context *ctx)
{
    if (ctx)
        __atomic_store_n(&ctx->cancel_flag, 1, __ATOMIC_RELEASE);
}

int cb_context_cancelled(const cb_context *ctx)
{
    return ctx ? __atomic_load_n(&ctx->cancel_flag, __ATOMIC_ACQUIRE) : 0;
}

int cb_context_threads(const cb_context *ctx)
{
    return ctx ? ctx->threads : 0;
}

static void context_lock(cb_context *ctx)
{
    while (__atomic_exchange_n(&ctx->lock, 1, __ATOMIC_ACQUIRE))
        ;
}

static void context_unlock(cb_context *ctx)
{
    __atomic_store_n(&ctx->lock, 0, __ATOMIC_RELEASE);
}

void cb_context_progress_reset(cb_context *ctx)
{
    if (!ctx)
        return;
    context_lock(ctx);
    ctx->last_fraction = -1.0;
    context_unlock(ctx);
}

void cb_context_progress(cb_context *ctx, double done, double total, const char *stage)
{
    if (!ctx || !ctx->progress || !(total > 0))
        return;
    double f = done / total;
    f = f < 0 ? 0 : f > 1 ? 1 : f;
    context_lock(ctx);
    if (f > ctx->last_fraction) {
        ctx->last_fraction = f;
        ctx->progress(ctx->user, f, stage ? stage : "");
    }
    context_unlock(ctx);
}
